"""Numba functions built into small shared libraries, loaded with ctypes: code that runs
compiled without importing numba at run time (the OBJ scanner of ``scene``, the numba
variant's render and hierarchy builder). See ``compiled.library``."""


class KernelFolderError(RuntimeError):
    """No private folder for compiled code can be had (``RTC_NUMBA_KERNELS`` names a folder
    that is not one, another user's ...): one line for the user."""
