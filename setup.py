"""Build the C extensions: swarmpath.search (grid A*, distance fields, lazy distance tables),
swarmpath.control.pibt (one PIBT step), swarmpath.control.evasion (the walker-evasion value),
swarmpath.control.orca (ORCA's linear programs) and swarmpath.optim (one particle-swarm move);
all other metadata lives in pyproject.toml."""
from setuptools import Extension, setup

setup(
    ext_modules=[
        Extension(
            "swarmpath.search._gridsearch",
            ["src/swarmpath/search/_gridsearch.c"],
            extra_compile_args=["-O3"],
        ),
        Extension(
            "swarmpath.search._lazydist",
            ["src/swarmpath/search/_lazydist.c"],
            extra_compile_args=["-O3"],
        ),
        Extension(
            "swarmpath.control.pibt._pibt",
            ["src/swarmpath/control/pibt/_pibt.c"],
            extra_compile_args=["-O3"],
        ),
        Extension(
            "swarmpath.control.evasion._evasion",
            ["src/swarmpath/control/evasion/_evasion.c"],
            extra_compile_args=["-O3"],
        ),
        Extension(
            "swarmpath.optim._swarmstep",
            ["src/swarmpath/optim/_swarmstep.c"],
            # no fused multiply-add: the loop must round exactly as the numpy reference kernels
            extra_compile_args=["-O3", "-ffp-contract=off"],
        ),
        Extension(
            "swarmpath.control.orca._orcalp",
            ["src/swarmpath/control/orca/_orcalp.c"],
            # no fused multiply-add: the loop must round exactly as the Python reference (lp.py)
            extra_compile_args=["-O3", "-ffp-contract=off"],
        ),
    ]
)
