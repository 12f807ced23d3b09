"""clutchlab: batch parameter studies of helicopter and UAV drivetrain clutches.

Physics modules are pure, vectorised numpy functions in SI units; studies turn a design of
experiments into a labelled :class:`xarray.Dataset`; :mod:`clutchlab.store` writes and reads
those Datasets as HDF5 (h5netcdf engine).
"""
from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("clutchlab")
except PackageNotFoundError:  # running from a source tree that was never installed
    __version__ = "0+unknown"

__all__ = ["__version__"]
