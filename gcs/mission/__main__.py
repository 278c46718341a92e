"""``python -m gcs.mission SCENARIO [--engine processes|lockstep] [--mode paper|improved] ...``."""

import sys

from gcs.mission.cli import main

sys.exit(main())
