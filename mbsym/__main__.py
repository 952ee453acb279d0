"""``python -m mbsym``: same as the ``mbsym`` console script."""

import sys

from .cli import main

sys.exit(main())
