"""Numpy models of how the world's sensors err: the simulated OpenPose (`pose_detector`) and
its error model (`detector_model`), calibrated to measured OpenPose errors."""
