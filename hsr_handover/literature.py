"""Figures from the literature that both the simulated person and the robot's models cite.

The person (the world) is made as imprecise as these studies found people to be; the robot's
recogniser models people with the same figures. They are two parameters that start from one
measurement, so the measurement lives here once.
"""

from __future__ import annotations

BREUER_POINTING_ERROR_DEG = 7.3
"""Mean error of the forearm's pointing direction (Breuer et al. 2010), whose robot found 86.6 %
of targets 23 cm apart from it."""
BREUER_TARGETS_FOUND = 0.866
"""Share of targets 23 cm apart that the forearm's pointing direction found (Breuer et al.
2010)."""
STIEFELHAGEN_HEAD_FRACTION = 0.689
"""The head's share of a gaze shift; the eyes make the rest (Stiefelhagen and Zhu 2002)."""
HEAD_FRACTION_SD = 0.08
"""How much the head's share of a gaze shift varies between people (sd). Not a measurement:
Stiefelhagen and Zhu report the share over their subjects; the simulated people are drawn with
this spread, and the robot's recogniser allows for twice it."""
