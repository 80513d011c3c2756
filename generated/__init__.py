"""Generated code of the built-in robots (one folder each), written by `make derive`.

This file only marks the folder as a package, so that `pip install .` ships the C sources.
"""
