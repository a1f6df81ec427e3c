"""Grid solver backends, one module each (STYLE.md, point 5), named in
:data:`plansynth.grid.result.BACKENDS` and imported when asked for by name."""
