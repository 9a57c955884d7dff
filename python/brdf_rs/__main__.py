"""``python -m brdf_rs`` is the ``brdf-rs`` command."""

import sys

from .cli import main

sys.exit(main())
