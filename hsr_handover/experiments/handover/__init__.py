"""The handover experiment (paper 4.3): its trials, their scoring against the truth, the report."""
