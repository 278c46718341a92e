"""The ground station's command lines share one rule: a usage error is one line on stderr and exit code 2."""

from __future__ import annotations

import argparse
import sys

EXIT_USAGE = 2


class OneLineArgumentParser(argparse.ArgumentParser):
    """argparse, but a usage error prints ``<label>: <message>`` and exits with :data:`EXIT_USAGE`."""

    def __init__(self, *args: object, label: str, **kwargs: object) -> None:
        super().__init__(*args, **kwargs)  # type: ignore[arg-type]
        self.label = label

    def error(self, message: str) -> None:  # type: ignore[override]
        print(f"{self.label}: {message}", file=sys.stderr)
        raise SystemExit(EXIT_USAGE)
