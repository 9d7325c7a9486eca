"""When the robot's per-frame systems run, relative to the camera's captures.

Drake computes every update due at one instant from the state just before it, so a system that
updates at a capture instant reads the previous frame. Systems that must read the frame just
captured update a little after it: the scene map `PROCESSING_DELAY_S` after, and systems that
read the map's update of that frame (the intent estimator) a further delay after that. Far below
a frame period (33 ms at 30 Hz), the delays change nothing else.
"""

from __future__ import annotations

PROCESSING_DELAY_S = 1e-3
