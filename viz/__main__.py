"""``python -m viz`` runs the ``silo4`` command line."""

from .cli import main

raise SystemExit(main())
