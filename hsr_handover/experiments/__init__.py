"""The paper's experiments, one sub-package each, and what they share: the trial runner, the
generated layouts, the trial classes and the scoring against the world's truth."""
