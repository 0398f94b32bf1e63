"""Built-in MovingAI benchmark maps and scens (package data; see README.md in this folder)."""
from pathlib import Path

#: The folder holding the built-in .map and .scen files.
MOVINGAI = Path(__file__).parent
