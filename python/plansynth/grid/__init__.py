"""Reactive grid controllers (Chasins & Newcomb, SYNT 2016)."""
