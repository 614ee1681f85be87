"""Writers: CSV histories, HDF5 fields with XDMF, interface and column records."""
