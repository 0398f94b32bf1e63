"""Shortest collision-free paths, as the yardstick for the swarm planners' lengths.

:func:`visibility_shortest_path` builds a visibility graph whose nodes are the start, the goal,
the corners of rectangles and polygons and the vertices of regular polygons circumscribed
about the circles (``circle_sides`` sides; every obstacle grown by the robot's radius, a
grown corner replaced by a circumscribed circle of that radius), joins every pair of nodes
whose segment is free by ``World.static_hits`` (exact), and runs Dijkstra. Because the
circumscribed polygons contain the circles, the path it returns is collision-free and its
length is an upper bound of the true shortest length that exceeds it only along arcs, by the
factor 1/cos(pi/circle_sides) (0.03 % for 128 sides): abbas-case1 gives 14.46496 against the
analytic 14.46483. Worlds with a raster map fall back to A* on a fine grid followed by greedy
string pulling (:func:`grid_shortest_path`), a looser upper bound (+0.25 % on abbas-case1 at
resolution 0.05).
"""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from swarmpath.planning.grid_paths import cells_to_polyline
from swarmpath.search import astar
from swarmpath.world.grid import rasterize
from swarmpath.world.shapes import Circle, Rect

FloatArray = NDArray[np.float64]


def _length(p: FloatArray) -> float:
    return float(np.linalg.norm(np.diff(p, axis=0), axis=1).sum())


def shortcut_path(world, path: ArrayLike, radius: float = 0.0) -> FloatArray:
    """Greedy string pulling with exact geometry: from each kept vertex, jump to the farthest
    later vertex the straight segment reaches without a static hit (``World.static_hits``).

    path (n_points, 2), collision-free -> a collision-free path (m, 2), m <= n_points, with the
    same ends and a length no larger.
    """
    p = np.asarray(path, dtype=float)
    if len(p) <= 2:
        return p.copy()
    out = [p[0]]
    i = 0
    n = len(p)
    while i < n - 1:
        cand = np.arange(i + 1, n)
        hits = world.static_hits(np.repeat(p[i][None], len(cand), axis=0), p[cand], np.full(len(cand), radius))
        free = np.flatnonzero(~hits)
        j = int(cand[free[-1]]) if len(free) else i + 1
        out.append(p[j])
        i = j
    return np.asarray(out)


def _corner_ring(points: FloatArray, radius: float, sides: int) -> FloatArray:
    """Vertices of regular ``sides``-gons circumscribed about circles of ``radius`` around each
    point (k, 2) -> (k * sides, 2), pushed out by a relative 1e-9 so their edges only touch."""
    ang = 2 * np.pi * np.arange(sides) / sides
    rr = radius / np.cos(np.pi / sides) * (1 + 1e-9)
    ring = np.column_stack([np.cos(ang), np.sin(ang)]) * rr
    return (points[:, None, :] + ring[None]).reshape(-1, 2)


def visibility_nodes(world, radius: float = 0.0, circle_sides: int = 128, corner_sides: int = 32) -> FloatArray:
    """Candidate corner points of shortest paths among the world's static obstacles grown by
    ``radius`` (see the module docstring); shape (n_nodes, 2), free ones only."""
    nodes = []
    for shape in world.obstacles:
        if isinstance(shape, Circle):
            nodes.append(_corner_ring(np.asarray(shape.center, float)[None], shape.radius + radius, circle_sides))
            continue
        if isinstance(shape, Rect):
            (x0, y0), (x1, y1) = shape.min, shape.max
            corners = np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]], float)
        else:
            corners = shape.vertices
        if radius > 0:
            nodes.append(_corner_ring(corners, radius, corner_sides))
        else:
            nodes.append(corners)
    if not nodes:
        return np.zeros((0, 2))
    pts = np.vstack(nodes)
    ok = world.bounds.contains(pts, radius) & ~world.static_hits(pts, pts, np.full(len(pts), radius))
    return pts[ok]


def visibility_shortest_path(world, robot, circle_sides: int = 128) -> tuple[FloatArray | None, float | None]:
    """Shortest path of ``robot`` on the visibility graph (module docstring): (path (m, 2),
    length), or (None, None) when start and goal are not connected. Worlds with a raster map
    are not supported (ValueError): use :func:`grid_shortest_path`."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import dijkstra

    if world.static_map is not None:
        raise ValueError("visibility_shortest_path: worlds with a raster map are not supported")
    r = float(robot.radius)
    pts = np.vstack([np.asarray(robot.start, float)[None], np.asarray(robot.goal, float)[None],
                     visibility_nodes(world, r, circle_sides)])
    n = len(pts)
    i, j = np.triu_indices(n, k=1)
    free = np.zeros(len(i), dtype=bool)
    chunk = 200_000
    for k in range(0, len(i), chunk):
        a, b = pts[i[k:k + chunk]], pts[j[k:k + chunk]]
        free[k:k + chunk] = ~world.static_hits(a, b, np.full(len(a), r))
    i, j = i[free], j[free]
    w = np.linalg.norm(pts[i] - pts[j], axis=1)
    graph = coo_matrix((np.concatenate([w, w]), (np.concatenate([i, j]), np.concatenate([j, i]))), shape=(n, n))
    dist, pred = dijkstra(graph.tocsr(), indices=0, return_predecessors=True)
    if not np.isfinite(dist[1]):
        return None, None
    order = [1]
    while order[-1] != 0:
        order.append(int(pred[order[-1]]))
    path = pts[order[::-1]]
    return path, _length(path)


def astar_polyline(world, robot, grid) -> FloatArray | None:
    """The A* path of ``robot`` on ``grid`` as a world polyline (n_points, 2) from the exact
    start to the exact goal through the cells' centres, string-pulled with the exact geometry
    when it is collision-free; None when the grid has no path. Start and goal cells on the
    workspace's far edge (e.g. a goal at (10, 10) in a 10 x 10 workspace) are moved into the
    grid."""
    hi = np.array([grid.width - 1, grid.height - 1])
    start = np.clip(grid.cell_of(robot.start), 0, hi)
    goal = np.clip(grid.cell_of(robot.goal), 0, hi)
    if not (grid.is_free(start) and grid.is_free(goal)):
        return None
    result = astar(grid, start, goal)
    if not result:
        return None
    poly = cells_to_polyline(grid, result.cells, robot.start, robot.goal)
    if world.static_hits(poly[:-1], poly[1:], np.full(len(poly) - 1, robot.radius)).any():
        return poly          # joining the exact ends to the cells clipped an obstacle: keep the cells
    return shortcut_path(world, poly, robot.radius)


def grid_shortest_path(world, robot, resolution: float = 0.05) -> tuple[FloatArray | None, float | None]:
    """A* on the world rasterised at ``resolution`` for the robot's radius, then greedy string
    pulling with the exact geometry (:func:`astar_polyline`): (path (m, 2), length), or
    (None, None) without a grid path."""
    poly = astar_polyline(world, robot, rasterize(world, resolution, robot.radius))
    return (None, None) if poly is None else (poly, _length(poly))


def shortest_path_reference(world, robot) -> tuple[FloatArray | None, float | None]:
    """The yardstick: :func:`visibility_shortest_path`, or :func:`grid_shortest_path` (0.05)
    for worlds with a raster map."""
    if world.static_map is not None:
        return grid_shortest_path(world, robot)
    return visibility_shortest_path(world, robot)
