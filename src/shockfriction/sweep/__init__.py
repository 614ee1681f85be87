"""Parameter sweeps and calibration: local process pool by default, Dask when asked."""
