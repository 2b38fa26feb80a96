import sys

from gmr_studio.core.cli import main

sys.exit(main())
