"""Grading a submission: the grader, its statistical tests, its sandbox."""
