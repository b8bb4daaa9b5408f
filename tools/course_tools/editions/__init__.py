"""Editions: solution markers, the student edition, starter releases, autograder zips."""
