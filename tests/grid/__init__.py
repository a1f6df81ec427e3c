"""Tests of the grid half (a package so test module names cannot clash with other parts)."""
