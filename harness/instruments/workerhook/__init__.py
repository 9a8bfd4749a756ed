"""Start-up hook for worker processes whose allocations the harness counts (see
sitecustomize.py); a package only so that installs ship it."""
