"""``python -m explorer.app``: the ``explore`` command."""

import sys

from . import main

sys.exit(main())
