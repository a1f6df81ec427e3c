"""Benchmarks reproducing both papers' evaluations side by side with peers."""
