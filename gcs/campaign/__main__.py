"""``python -m gcs.campaign``: see :mod:`gcs.campaign.cli`."""

import sys

from gcs.campaign.cli import main

if __name__ == "__main__":
    sys.exit(main())
