"""``python -m origami_cad``: the ``origami-cad`` command, for an environment whose
scripts folder is not on the ``PATH``."""

import sys

from origami_cad.cli import main

if __name__ == "__main__":
    sys.exit(main())
