"""Build the C extension of swarmpath.search (grid A* and distance fields); all other
metadata lives in pyproject.toml."""
from setuptools import Extension, setup

setup(
    ext_modules=[
        Extension(
            "swarmpath.search._gridsearch",
            ["src/swarmpath/search/_gridsearch.c"],
            extra_compile_args=["-O3"],
        )
    ]
)
