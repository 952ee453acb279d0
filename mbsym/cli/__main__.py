"""``python -m mbsym.cli``: same as the ``mbsym`` console script."""

import sys

from . import main

sys.exit(main())
