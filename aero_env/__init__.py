"""aero-env: the paper-craft aerial acrobat robot as a pymunk world and analytical models."""

__version__ = "0.1.0"
