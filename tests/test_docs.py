"""The documentation works as written: every command of README.md and docs/*.md runs verbatim
in a fresh clone's layout (only the files git tracks), every Python example runs, and the
guide names every registered algorithm.

What runs: indented lines and ``sh`` blocks that start with ``swarmpath``, and ``python``
blocks. What does not: installation lines (CI runs the README's) and ``python benchmarks/...``
(benchmarks need the [bench] extra and run on demand)."""
from __future__ import annotations

import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).parents[1]
PAGES = ["README.md", *sorted(str(p.relative_to(ROOT)) for p in (ROOT / "docs").rglob("*.md"))]


def _blocks(text: str) -> tuple[list[str], list[str]]:
    """(shell commands, python code blocks) of a Markdown page."""
    commands, code = [], []
    fence = re.compile(r"^```(\w*)\n(.*?)^```", re.S | re.M)
    for lang, body in fence.findall(text):
        if lang == "python":
            code.append(body)
        elif lang in ("sh", "bash", "console"):
            commands += [line for line in body.splitlines() if line.strip()]
    outside = fence.sub("", text)
    commands += [line[4:] for line in outside.splitlines() if re.match(r"^    (swarmpath|python3? -m swarmpath) ", line)]
    keep = []
    for line in commands:
        line = line.split("  #")[0].split(" # ")[0].strip()
        if line.startswith("swarmpath ") or line.startswith("python examples/"):
            keep.append(line)
    return keep, code


def _commands() -> list[tuple[str, list[str]]]:
    """Each page with its commands, in order (later ones may read what earlier ones wrote)."""
    out = []
    for page in PAGES:
        cmds, _ = _blocks((ROOT / page).read_text(encoding="utf-8"))
        if cmds:
            out.append((page, cmds))
    return out


def _code() -> list[tuple[str, int, str]]:
    out = []
    for page in PAGES:
        _, code = _blocks((ROOT / page).read_text(encoding="utf-8"))
        out += [(page, k, c) for k, c in enumerate(code)]
    return out


@pytest.fixture(scope="module")
def clone(tmp_path_factory) -> Path:
    """The tracked files of the repository, copied (a fresh clone's layout, no build output)."""
    if shutil.which("git") is None or not (ROOT / ".git").exists():
        pytest.skip("needs a git checkout")
    files = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True, check=True).stdout.split()
    dest = tmp_path_factory.mktemp("clone")
    for f in files:
        if f.startswith(("src/", ".ci/")) or not (ROOT / f).is_file():
            continue   # the installed package is what runs; its source tree is not needed
        (dest / f).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(ROOT / f, dest / f)
    return dest


def _swarmpath() -> list[str]:
    exe = shutil.which("swarmpath", path=str(Path(sys.executable).parent))
    return [exe] if exe else [sys.executable, "-m", "swarmpath.cli"]


@pytest.mark.slow
@pytest.mark.parametrize("page, commands", _commands(), ids=lambda v: v if isinstance(v, str) else "")
def test_documented_commands_run_verbatim(clone: Path, page: str, commands: list[str]) -> None:
    for command in commands:
        argv = shlex.split(command)
        argv = _swarmpath() + argv[1:] if argv[0] == "swarmpath" else [sys.executable, *argv[1:]]
        p = subprocess.run(argv, cwd=clone, capture_output=True, text=True, timeout=900)
        assert p.returncode == 0, f"{page}: `{command}` exited {p.returncode}: {p.stderr[-500:]}"
        assert "Traceback" not in p.stderr, f"{page}: `{command}`"


@pytest.mark.slow
@pytest.mark.parametrize("page, index, code", _code(), ids=lambda v: str(v)[:40])
def test_documented_python_runs(clone: Path, page: str, index: int, code: str) -> None:
    script = clone / f"doc_example_{index}.py"
    script.write_text(code, encoding="utf-8")
    p = subprocess.run([sys.executable, str(script)], cwd=clone, capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, f"{page}, python block {index}: {p.stderr[-800:]}"


def test_the_guide_names_every_registered_algorithm() -> None:
    from swarmpath.registry import CONTROLLERS, FUNCTIONS, MOTIONS, OPTIMIZERS, PLANNERS, REPRODUCTIONS

    text = (ROOT / "docs" / "guide.md").read_text(encoding="utf-8")
    names = text[text.index("### Names"):text.index("## The Python API")]
    missing = [n for reg in (PLANNERS, CONTROLLERS, OPTIMIZERS, FUNCTIONS, MOTIONS, REPRODUCTIONS)
               for n in reg.names() if f"`{n}`" not in names]
    assert missing == []
