"""Rotation-representation sanity experiments (thesis chapter 2, Table 2.1)."""
