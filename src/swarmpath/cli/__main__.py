"""``python -m swarmpath.cli``."""
from swarmpath.cli import main

main()
