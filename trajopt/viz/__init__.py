"""Drawing on top of the pipeline: the only part of the project that imports matplotlib.

:mod:`trajopt.viz.drawing` draws tracks, configuration spaces, skeletons and plans; :mod:`trajopt.viz.plotting`
the summary figure of a trajectory; :mod:`trajopt.viz.animation` the animations of plans and trajectories;
:mod:`trajopt.viz.layout` draws graph tracks and graph plans, :mod:`trajopt.viz.layout_animation` animates
robots on them.
"""
