"""The reactive synthesis competition's robot benchmarks as plansynth sees them.

* :mod:`~plansynth.grid.syntcomp.aiger`: AIGER circuits (SYNTCOMP's safety games) and a
  batched simulator;
* :mod:`~plansynth.grid.syntcomp.moving_obstacle`: Ehlers' "Robot-on-a-grid Moving
  Obstacle Evasion" family as an explicit safety game, with a brute-force solver;
* :mod:`~plansynth.grid.syntcomp.omega_game`: the same game posed to ``omega`` (the
  BDD-based GR(1) solver under TuLiP), the peer;
* :mod:`~plansynth.grid.syntcomp.robot_grid`: the TLSF ``robot_grid`` maps (stations,
  doors, walls, one obstacle) as plain data.

Nothing here imports ``omega`` or ``dd`` until :mod:`omega_game` is imported.
"""
