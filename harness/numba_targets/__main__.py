"""``python -m harness.numba_targets``: the numba variant's figures, printed."""

import sys

from harness.numba_targets import main

sys.exit(main())
