"""The command line of ./course: the verbs, the suite, the book."""
