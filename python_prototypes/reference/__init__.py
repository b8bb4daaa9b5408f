"""Independent numpy references for the chapter images (COURSE.md, 'Checks')."""
