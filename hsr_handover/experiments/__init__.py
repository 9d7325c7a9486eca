"""Experiments of the paper (layer 3): batches and measurements over the station."""
