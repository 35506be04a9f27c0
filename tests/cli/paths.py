"""Where the checkout and its examples are (shared by the CLI tests)."""

from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
EXAMPLES = REPO / "examples"
