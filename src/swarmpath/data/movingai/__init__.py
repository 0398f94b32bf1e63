"""Built-in MovingAI benchmark maps and scens (package data; see README.md in this folder)."""
