"""``python -m viz`` runs the ``silo4`` command line."""

from viz.cli.main import main

raise SystemExit(main())
