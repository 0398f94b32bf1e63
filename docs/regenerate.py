"""Rewrite the documentation generated from the code: the JSON Schemas of scenario files
(docs/scenario.schema.json) and of sweep suites (docs/suite.schema.json), and the list of
motion models in docs/scenarios.md. Run it after adding a motion model or changing the
scenario or suite models; the tests fail until it has run.

    python docs/regenerate.py
"""
from __future__ import annotations

import json
import re
from pathlib import Path

from swarmpath.bench.sweep.suite import suite_json_schema
from swarmpath.world.motions import motions_markdown
from swarmpath.world.scenario import scenario_json_schema

DOCS = Path(__file__).parent


def main() -> None:
    (DOCS / "scenario.schema.json").write_text(json.dumps(scenario_json_schema(), indent=2) + "\n", encoding="utf-8")
    (DOCS / "suite.schema.json").write_text(json.dumps(suite_json_schema(), indent=2) + "\n", encoding="utf-8")
    page = DOCS / "scenarios.md"
    text = page.read_text(encoding="utf-8")
    block = re.compile(r"(<!-- motions:begin[^\n]*-->\n).*?(<!-- motions:end -->)", re.S)
    page.write_text(block.sub(lambda m: m.group(1) + motions_markdown() + "\n" + m.group(2), text), encoding="utf-8")
    print("regenerated docs/scenario.schema.json, docs/suite.schema.json and the motion list in docs/scenarios.md")


if __name__ == "__main__":
    main()
