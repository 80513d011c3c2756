"""Mutation testing of the runtime (``make mutate``): see ``python -m mutation --help``."""
