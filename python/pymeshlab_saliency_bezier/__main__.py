"""python -m pymeshlab_saliency_bezier ...: the saliency-bezier-smooth command."""
import sys

from .cli import main

sys.exit(main())
