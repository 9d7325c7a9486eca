"""Recorded sessions: an RGB-D session folder written during a run and read back, the robot's
perception run offline on one (`offline_intent`), and the check of OpenPose files."""
