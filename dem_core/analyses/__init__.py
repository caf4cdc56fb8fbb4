"""What is done with many runs: threshold searches, parametric sweeps, response spectra, stiffness convergence,
fragility curves."""
