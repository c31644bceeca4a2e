"""``python -m resonant`` runs the command line."""

from resonant.cli import program

program()
