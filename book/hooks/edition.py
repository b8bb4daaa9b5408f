"""The book's two editions (tools/course_tools/editions/editions.py). ./course book builds the instructors'
edition: the code as it is, solutions included, and each chapter's answer notes
(`??? answers` blocks). ./course book --student sets COURSE_BOOK_EDITION=student, and
this hook turns the same pages into the edition to publish: snippets read a copy of the
sources in which every SOLUTION block, and every later chapter's copy of one, is the
starter's TODO and stub (build/book-student/sources, written before each build, diffs
included), the answer notes are left out, and the site goes to book/site-student."""

from __future__ import annotations

from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
from course_tools.cli.book import book_diff_pairs  # which checkpoint diffs the book shows
from course_tools.editions import editions  # tools/course_tools/editions/editions.py: the student edition's sources


def on_config(config):
    if editions.edition() == "student":
        # Only the student copy: a listing it lacks fails the strict build (check_paths)
        # instead of falling back to the solution.
        config.mdx_configs["pymdownx.snippets"]["base_path"] = [str(editions.STUDENT_SOURCES)]
        config.site_dir = str(editions.STUDENT_SITE)
        config.site_name = f"{config.site_name} (student edition)"
    return config


def on_pre_build(config):
    # After hooks/setup_tables.py's on_pre_build: the setup page's tables are written.
    if editions.edition() == "student":
        editions.write_student_sources(ROOT, editions.STUDENT_SOURCES,
                                       book_diff_pairs())


def on_page_markdown(markdown, page, config, files):
    if editions.edition() == "student":
        return editions.drop_answers(markdown)
    return markdown
