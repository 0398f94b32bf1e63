"""Perception: the vision part of the PSO-prediction paper (2013, section 6).

An overhead camera image is turned into positions by colour: a pixel belongs to a colour
class when its Euclidean RGB distance to the class's reference colour is below a tolerance
(eq. 9); connected regions of such pixels give objects, their centroids the positions
(:mod:`swarmpath.perception.colour`). :mod:`swarmpath.perception.render` draws a world state
as such an image, with known colours, so that the pipeline image -> positions -> prediction
-> plan can be run and tested end to end.
"""
from swarmpath.perception.colour import PixelFrame, Region, colour_mask, find_regions, load_image, rgb_distance
from swarmpath.perception.render import Palette, render_state, save_png

__all__ = ["Palette", "PixelFrame", "Region", "colour_mask", "find_regions", "load_image", "render_state",
           "rgb_distance", "save_png"]
