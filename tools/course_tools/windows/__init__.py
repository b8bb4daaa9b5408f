"""The course on Windows, checked from Linux: a MinGW-w64 cross-build of every chapter
(cross_build.py) whose programs the chapters' own image checks run under Wine."""
