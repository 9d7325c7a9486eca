"""The robot: what runs on the HSR, a Diagram joined to the world only by ports.

`builder` builds the Diagram (`build_robot`); `perception_wiring` its perception part. The
algorithms it runs are in `perception`, `intent`, `effectivity`, `planning` and `handover`; the
Drake systems that run them in `systems`.
"""
