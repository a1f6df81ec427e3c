"""The ``plansynth reach`` commands, one module per command (``solve``, ``validate``,
``plot``, ``table``) and what several of them share (the result table, the mission
readings the command line sets, the limits of the size options, reading a result
file). :mod:`plansynth.reach.cli` assembles them into the Typer app."""
