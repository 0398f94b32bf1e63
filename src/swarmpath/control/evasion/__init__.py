"""Evading random walkers: the exact chance of being caught within a horizon when playing best
(:mod:`~swarmpath.control.evasion.walker`), two walkers played together
(:mod:`~swarmpath.control.evasion.pair`), and their use by grid controllers
(:mod:`~swarmpath.control.evasion.risk`)."""
from swarmpath.control.evasion.pair import PAIR_RADIUS, pair_move_risk
from swarmpath.control.evasion.risk import EvasionRisk, check_evasion, vetoed_last, walker_vetoed
from swarmpath.control.evasion.walker import EVASION_RADIUS, WalkerEvasion, WalkerModel, walker_model

__all__ = ["EvasionRisk", "check_evasion", "walker_vetoed", "vetoed_last", "WalkerEvasion", "WalkerModel",
           "walker_model", "EVASION_RADIUS", "PAIR_RADIUS", "pair_move_risk"]
