"""The effectivity figures (paper figs. 8 and 14) on a scenario."""
