"""Colour recognition (eq. 9) and the image -> positions -> prediction -> plan pipeline."""
from __future__ import annotations

import numpy as np
import pytest

from swarmpath.control.pso_predictive.prediction import predict_linear
from swarmpath.control.pso_predictive import PredictivePSOController
from swarmpath.world.geometry import point_segment_distance
from swarmpath.errors import ConfigError
from swarmpath.perception import PixelFrame, colour_mask, find_regions, load_image, render_state, rgb_distance, save_png
from swarmpath.perception.colour import centroids
from swarmpath.perception.render import Palette, add_noise
from swarmpath.rng import make_rng
from swarmpath.control.observation import Observation, SensingConfig
from swarmpath.sim.sensing import sense
from swarmpath.world import RectBounds, Robot, World, load_scenario
from swarmpath.world.moving import Bounce, MovingObstacle
from swarmpath.world.shapes import Circle

PALETTE = Palette()
FRAME = PixelFrame(20.0)


def _match(found: np.ndarray, truth: np.ndarray) -> np.ndarray:
    """Distance from each true position to the nearest found one (world units)."""
    return np.linalg.norm(truth[:, None] - found[None], axis=-1).min(axis=1)


def test_rgb_distance_and_threshold_by_hand():
    image = np.array([[[255, 140, 0], [255, 150, 0], [0, 0, 0]]], np.uint8)
    np.testing.assert_allclose(rgb_distance(image, (255, 140, 0)), [[0.0, 10.0, np.hypot(255, 140)]])
    np.testing.assert_array_equal(colour_mask(image, (255, 140, 0), 10.0), [[True, False, False]])  # D < t
    np.testing.assert_array_equal(colour_mask(image, (255, 140, 0), 10.5), [[True, True, False]])
    with pytest.raises(ConfigError):
        colour_mask(image, (0, 0, 0), 0.0)


def test_regions_are_connected_components_with_pixel_centre_centroids():
    image = np.full((6, 8, 3), 255, np.uint8)
    image[1:3, 1:3] = 0          # 2x2 block: centroid (2.0, 2.0) in pixels
    image[4, 6] = 0              # lone pixel: centroid (6.5, 4.5)
    regions = find_regions(image, (0, 0, 0), 30, frame=PixelFrame(2.0))
    assert [r.n_pixels for r in regions] == [4, 1]
    assert regions[0].centroid_px == (2.0, 2.0) and regions[0].centroid == (1.0, 1.0)
    assert regions[1].centroid_px == (6.5, 4.5)
    assert len(find_regions(image, (0, 0, 0), 30, min_pixels=2)) == 1


@pytest.mark.parametrize("seed", range(5))
def test_rendered_positions_recovered_within_one_pixel_with_noise(seed):
    world = load_scenario("prediction2013-14")
    rng = make_rng(seed, "test-colour")
    robots = world.starts + rng.uniform(-0.4, 0.4, world.starts.shape) + np.array([0.0, rng.uniform(0, 0.5)])
    obstacle = np.array([[rng.uniform(9.0, 11.0), rng.uniform(14.0, 16.0)]])
    image = add_noise(render_state(world, robots, obstacle, frame=FRAME), sigma=20.0, rng=rng)
    found_robots = centroids(find_regions(image, PALETTE.robot, 70, frame=FRAME, min_pixels=20))
    found_obstacle = centroids(find_regions(image, PALETTE.moving, 70, frame=FRAME, min_pixels=20))
    found_static = find_regions(image, PALETTE.static, 50, frame=FRAME, min_pixels=50)
    assert len(found_robots) == world.n_robots and len(found_obstacle) == 1 and len(found_static) == 5
    one_pixel = 1.0 / FRAME.pixels_per_unit
    assert _match(found_robots, robots).max() < one_pixel
    assert _match(found_obstacle, obstacle).max() < one_pixel


def test_png_round_trip(tmp_path):
    world = load_scenario("prediction2013")
    image = render_state(world, world.starts, frame=FRAME)
    assert image.shape == (480, 640, 3)                        # the paper's 640 x 480 pixel world
    back = load_image(save_png(image, tmp_path / "state.png"))
    np.testing.assert_array_equal(back, image)
    # the moving obstacle's start is the paper's pixel (200, 300) of Figure 15
    found = find_regions(back, PALETTE.moving, 30, frame=FRAME)
    assert found[0].centroid_px == pytest.approx((200.0, 300.0), abs=0.5)
    with pytest.raises(ConfigError):
        load_image(tmp_path / "missing.png")


def test_pipeline_image_to_positions_to_prediction_to_plan():
    """Two noisy camera frames -> obstacle and robot positions -> linear prediction -> one
    PSO step: the chosen move keeps clear of where the obstacle really goes next."""
    velocity = (0.0, 0.4)
    obstacle = MovingObstacle("D", Circle((0, 0), 1.0), (8.0, 3.0), velocity, Bounce())
    world = World(RectBounds(16, 12), robots=(Robot("a", (5.5, 6.0), (13.0, 6.0), 0.5, 0.6),),
                  moving_obstacles=(obstacle,), name="crossing")
    rng = make_rng(0, "test-pipeline")
    truth = [np.array([[8.0, 3.0 + 0.4 * k]]) for k in range(8)]
    robot = np.array([[5.5, 6.0]])
    frames = [add_noise(render_state(world, robot, truth[k], frame=FRAME), 15.0, rng) for k in (6, 7)]
    seen = [centroids(find_regions(f, PALETTE.moving, 70, frame=FRAME, min_pixels=20)) for f in frames]
    seen_robot = centroids(find_regions(frames[1], PALETTE.robot, 70, frame=FRAME, min_pixels=20))
    assert np.abs(seen_robot - robot).max() < 0.05
    predicted = predict_linear(seen[0], seen[1], 1.0, 1.0)
    true_next = truth[7] + np.array(velocity)
    assert np.linalg.norm(predicted - true_next) < 3 / FRAME.pixels_per_unit   # 1 px per frame + 1 px

    controller = PredictivePSOController(turn_guard="never")   # trust the linear prediction
    controller.reset(world, None, make_rng(0, "controller"))
    obs = Observation(7, 1.0, seen_robot, world.goals, np.array([False]), seen[1], seen[0],
                      sense(seen_robot, seen[1], SensingConfig(), world.resolution))
    decision = controller.act(obs)
    move = decision.positions[0]
    assert np.linalg.norm(move - robot[0]) <= 0.6 + 1e-9
    # keeps clear of the obstacle's true sweep in the next step (phase 1)
    gap = point_segment_distance(move, truth[7][0], true_next[0])
    assert gap >= 1.0 + 0.5
