"""Campaigns: parameter sweeps over the virtual lab, local or Dask executors."""
