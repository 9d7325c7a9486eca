"""Closed-form kinematics on numpy arrays (layer 1): no Drake systems here."""
