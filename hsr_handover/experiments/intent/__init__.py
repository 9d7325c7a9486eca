"""The intent experiment (paper 4.2): its trials, the percepts recorded for replay, the report."""
