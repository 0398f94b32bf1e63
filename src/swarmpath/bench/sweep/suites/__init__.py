"""The built-in suites (``swarmpath bench NAME``): one YAML file each, read as package data."""
