"""ORCA (van den Berg, Guy, Lin & Manocha, "Reciprocal n-Body Collision Avoidance", ISRR 2011):
reciprocal collision avoidance in continuous space for disc robots, the ``orca`` controller,
a safety layer any continuous controller can put in front of its moves, and the guidance
(preferred velocities along plans or distance fields) every continuous controller can share.

Importing this package registers the ``orca`` controller.
"""
from swarmpath.control.orca.controller import ORCAController
from swarmpath.control.orca.core import ORCAParams, ORCASolver
from swarmpath.control.orca.guidance import Guidance, velocity_toward
from swarmpath.control.orca.safety import SafetyLayer

__all__ = ["Guidance", "ORCAController", "ORCAParams", "ORCASolver", "SafetyLayer", "velocity_toward"]
