"""The course's own tools: everything ./course does besides the chapters themselves.

Sub-packages by job, importing one way, from the top of this list to the bottom:

    cli/       the command line: one table of verbs (cli/verbs.py), the build folder,
               the suite, the book, the other verbs
    bench/     benchmarks against Mitsuba 3 and between the course's own chapters
    editions/  solution markers, the student edition, starter releases, autograder zips
    grading/   the grader, its statistics and its sandbox
    setup/     set-up in layers (standard library only: runs before .venv exists)

and the shared pieces every job may use, which import none of the above: paths,
chapters (the chapter listing), cmake_cache, manifests, reference_cache.
tests/python/tools/test_layout.py checks the direction and that nothing edits sys.path."""
