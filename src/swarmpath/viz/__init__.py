"""Pictures of worlds and runs; they read results and never run algorithms.

- :mod:`swarmpath.viz.style`: colours (one per robot), titles, Agg figures outside pyplot
- :mod:`swarmpath.viz.world_plot`: worlds, planned and executed paths, snapshots
- :mod:`swarmpath.viz.curves`: UTD curves, convergence curves, Pareto fronts, grouped bars
- :mod:`swarmpath.viz.potential_field`: the potential field of the APF planners
- :mod:`swarmpath.viz.animation`: GIF / MP4 of a trajectory
- :mod:`swarmpath.viz.html_replay`: the self-contained interactive HTML replay
- :mod:`swarmpath.viz.run_outputs`: what ``swarmpath run --out DIR`` writes
"""
