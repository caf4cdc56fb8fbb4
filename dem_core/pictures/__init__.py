"""Figures and animations of runs (these modules import matplotlib)."""
