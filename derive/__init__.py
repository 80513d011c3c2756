"""Build-time derivation: robot description -> SymPy equations -> CasADi C in generated/.

Needs SymPy (``pip install .[derive]``); the runtime package ``planar_sym`` never imports this.
"""
