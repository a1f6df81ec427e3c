"""The reactive synthesis competition's robot benchmarks, as plansynth reads them.

* :mod:`~plansynth.grid.syntcomp.aiger`: AIGER circuits (SYNTCOMP's safety games), read
  in both forms, and a batched simulator;
* :mod:`~plansynth.grid.syntcomp.moving_obstacle`: Ehlers' "Robot-on-a-grid Moving
  Obstacle Evasion" family (SYNTCOMP ``aiger/moving_obstacle``) as an explicit safety
  game, with its exact rules;
* :mod:`~plansynth.grid.syntcomp.safety`: the explicit solvers of that game (numpy, and
  a brute-force oracle over Python sets) and a checker of their certificates;
* :mod:`~plansynth.grid.syntcomp.moving_obstacle_circuit`: which bits of the benchmark's
  circuits are which, and one circuit step compared with one step of the game;
* :mod:`~plansynth.grid.syntcomp.omega_game`: the same game posed to ``omega`` (the
  BDD-based GR(1) solver under TuLiP), the peer;
* :mod:`~plansynth.grid.syntcomp.robot_grid`: SYNTCOMP's TLSF ``robot_grid`` maps
  (stations, doors, walls, one moving obstacle) as plain data, with their semantics.

Nothing here imports ``omega`` or ``dd`` until :mod:`omega_game` is used.
"""
