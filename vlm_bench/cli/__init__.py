"""Command-line interface (typer): thin layer over the Python API."""
