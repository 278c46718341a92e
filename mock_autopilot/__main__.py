"""``python -m mock_autopilot``: see :mod:`mock_autopilot.cli`."""

import sys

from mock_autopilot.cli import run

sys.exit(run())
