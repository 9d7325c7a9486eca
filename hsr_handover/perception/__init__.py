"""Perception algorithms (layer 1) on numpy arrays and images: camera geometry, point clouds,
object detection, the skeleton sensor model. No Drake systems here."""
