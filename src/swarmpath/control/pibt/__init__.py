"""PIBT (Okumura et al., AIJ 2022): the one-step core (:mod:`.core`, C loop in ``_pibt.c``)
and the registered ``pibt`` controller (:mod:`.controller`)."""
from swarmpath.control.pibt.controller import PIBTController
from swarmpath.control.pibt.core import StepResult, pibt_step

__all__ = ["PIBTController", "StepResult", "pibt_step"]
