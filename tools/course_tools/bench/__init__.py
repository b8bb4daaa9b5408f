"""Benchmarks: the course against Mitsuba 3, and its chapters against each other."""
