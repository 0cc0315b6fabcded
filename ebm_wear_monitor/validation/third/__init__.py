"""Third, independent validation world for the sim-to-real diagnosis (see README.md)."""
