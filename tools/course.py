#!/usr/bin/env python3
"""The front door's Python half: ./course runs this with the system's Python, and the
verbs re-run it in .venv once their layer is set up. The verbs themselves are in the
course_tools package beside this file (course_tools/cli/verbs.py: the table of verbs)."""

from course_tools.cli.verbs import main

if __name__ == "__main__":
    main()
