"""Hair: HairNet (thesis chapter 4)."""
