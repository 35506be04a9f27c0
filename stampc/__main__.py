import sys

from stampc.cli import main

sys.exit(main())
