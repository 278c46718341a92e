"""``python -m gcs.dashboard --mission NAME --connect tcp/HOST:7447 --port 8080``."""

import sys

from gcs.dashboard.cli import main

sys.exit(main())
