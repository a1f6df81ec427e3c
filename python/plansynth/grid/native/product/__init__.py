"""The native engine for the objectives beyond the paper's (reach within l, safety,
recurrence) and for obstacles with a block, a period or glitches: the product game of
the robot's cells and the obstacles' configurations.

Modules, bottom up: :mod:`.space` (the configurations, explored once), :mod:`.fixpoints`
(the robot's winning states per objective, and the obstacles' dual ones, as nested
fixpoints over robot-cell bit sets), :mod:`.strategy` (the moves each state may play,
and the obstacles' winning strategy), :mod:`.certify` (the obstacles' strategy checked
against every robot move: the certificate of a "no"), :mod:`.program` (a program of the
grammar that plays allowed moves on every state it reaches) and :mod:`.solve` (the
stages together).
"""
