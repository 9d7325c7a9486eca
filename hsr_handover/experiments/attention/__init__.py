"""The attention experiment (paper 4.1, figs. 9-12)."""
