"""hsr_handover: a Toyota HSR robot partner that perceives a person's pointing and gaze, picks up
the object meant and hands it over, after Ardilla et al., "Topological mapping based on
perceiving-acting cycle in sharing cognitive environments for robot partners"."""

__version__ = "0.1.0"
