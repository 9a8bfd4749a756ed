"""Numba functions built into small shared libraries, loaded with ctypes: code that runs
compiled without importing numba at run time (the OBJ scanner of ``scene``, the numba
variant's render and hierarchy builder). See ``compiled.library``."""
