"""Reach-avoid planning with linear dynamics (Shoukry et al., CDC 2016)."""
