"""Grid solver backends, one module each (STYLE.md, point 5). Importing a module
registers its backend with :func:`plansynth.grid.result.register_backend`."""
