"""One module per ``planar-sym`` subcommand; each defines ``register(subparsers)``.

``planar_sym.cli`` discovers them here, so adding a command is adding a file.
"""
