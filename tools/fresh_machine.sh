#!/usr/bin/env bash
# The fresh-machine check: the README's two commands, exactly as written, on a clean
# Debian or Ubuntu made with debootstrap. Nothing of this machine's is in the root but
# what a learner's machine would have: compilers, CMake, Ninja, git, the distribution's
# own python3 and venv. (The CA bundle, and the apt and pip configuration, are copied in so that apt
# and pip reach the package mirrors as they do here.)
#
#   tools/fresh_machine.sh SUITE [--chapter NN] [--gradescope NN] [--caches] [--keep]
#
#   SUITE         bookworm (Debian 12), trixie (Debian 13), jammy (Ubuntu 22.04,
#                 Gradescope's image: Python 3.10, OpenEXR 2.5) or noble (Ubuntu 24.04,
#                 WSL 2's default: Python 3.12); the Ubuntu roots have main and universe,
#                 with -updates and -security as an installed Ubuntu has. Playwright's
#                 browser download (the Ubuntu rows' book check) may be out of reach: the
#                 test layer then stops there, and the summary says so (exit code 3)
#   --chapter NN  run `./course test NN` instead of `./course test` (what .ci/run names:
#                 the whole test layer is set up and built, one chapter's checks run)
#   --run-only    only the README's first command, `./course run` (the run layer)
#   --gradescope NN  instead: lay the root out as Gradescope does (/autograder/source,
#                 /autograder/submission, /autograder/results), unpack the chapter's
#                 autograder zip (./course autograder NN), run its setup.sh, then grade
#                 the released starter and the solution with run_autograder; each
#                 results.json is checked against Gradescope's format
#                 (tools/course_tools/grading/gradescope_results.py): the solution full marks, the starter
#                 at most 10%
#   --caches      keep the root's caches between checks, as a learner's machine keeps
#                 them between runs: its ~/.cache (pip's wheels, the compiler cache,
#                 Mesa's shader cache, the course's reference cache) and apt's
#                 downloaded packages, in COURSE_FRESH_CACHE/SUITE-*. Nothing installed
#                 is kept: every package is installed and every tree built again. CI
#                 uses it; a first run on a new machine is the same check without it.
#   --keep        leave the root in place afterwards (to look inside)
#
# Prints each command's time, and ends with one line per command: "fresh SUITE: ...".
# Exit 0 when every command passed, 1 when one failed, 3 when the test layer's set-up
# could not download Playwright's Chromium (Ubuntu; nothing of the suite ran).
# Needs root (debootstrap, chroot, mounts). The debootstrapped base (before anything of
# the course is installed) is cached as a tarball in COURSE_FRESH_CACHE
# (default /var/tmp/course-fresh), keyed by suite and package list.
set -euo pipefail
# The whole script is one block, read before any of it runs: editing this file while a
# check is under way (it takes minutes) cannot change the running check.
{
usage() { sed -n '2,36p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
[ $# -ge 1 ] || usage
SUITE="$1"; shift
CHAPTER=""
GRADESCOPE=""
KEEP=0
CACHES=0
RUN_ONLY=0
while [ $# -gt 0 ]; do
  case "$1" in
    --chapter) CHAPTER="${2:?--chapter needs a chapter number}"; shift 2 ;;
    --gradescope) GRADESCOPE="${2:?--gradescope needs a chapter number}"; shift 2 ;;
    --keep) KEEP=1; shift ;;
    --run-only) RUN_ONLY=1; shift ;;
    --caches) CACHES=1; shift ;;
    *) usage ;;
  esac
done
case "$SUITE" in
  bookworm | trixie) UBUNTU=0 ;;
  jammy | noble) UBUNTU=1 ;;
  *) echo "fresh_machine: SUITE is bookworm, trixie, jammy or noble, not '$SUITE'" >&2; exit 2 ;;
esac
if [ "$(id -u)" -ne 0 ]; then
  echo "fresh_machine: needs root (debootstrap, chroot)" >&2
  exit 5
fi
if ! command -v debootstrap >/dev/null; then
  echo "fresh_machine: installing debootstrap" >&2
  apt-get update -qq && apt-get install -y -qq --no-install-recommends debootstrap >&2
fi

REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
MIRROR="${COURSE_DEBIAN_MIRROR:-http://deb.debian.org/debian}"
DEBOOTSTRAP_OPTIONS=()
DEBOOTSTRAP_SCRIPT=()
if [ "$UBUNTU" = 1 ]; then
  MIRROR="${COURSE_UBUNTU_MIRROR:-http://archive.ubuntu.com/ubuntu}"
  DEBOOTSTRAP_OPTIONS=(--components=main,universe)
  # An older debootstrap (Debian 12's) has no script for a newer Ubuntu; every Ubuntu
  # release since 7.10 is made by the same one, which its scripts link to.
  if [ ! -e "/usr/share/debootstrap/scripts/$SUITE" ]; then
    DEBOOTSTRAP_SCRIPT=(/usr/share/debootstrap/scripts/gutsy)
  fi
fi
# What a learner's machine has before the README: compilers, CMake, Ninja, git, Python.
BASE_PACKAGES="g++,cmake,ninja-build,git,python3,python3-venv,ca-certificates"
CACHE="${COURSE_FRESH_CACHE:-/var/tmp/course-fresh}"
KEY="$(echo "$SUITE $MIRROR $BASE_PACKAGES" | sha256sum | cut -c1-12)"
BASE_TAR="$CACHE/$SUITE-$KEY.tar"
ROOTFS="$(mktemp -d "${TMPDIR:-/var/tmp}/course-fresh-$SUITE.XXXXXX")"

MOUNTS=()
cleanup() {
  local i
  for ((i = ${#MOUNTS[@]} - 1; i >= 0; i--)); do umount -l "${MOUNTS[$i]}" 2>/dev/null || true; done
  if [ "$KEEP" = 1 ]; then echo "fresh_machine: root kept in $ROOTFS" >&2; else rm -rf "$ROOTFS"; fi
}
trap cleanup EXIT

seconds() { date +%s; }

# Ubuntu's archive key, which Debian does not ship: from Ubuntu's ubuntu-keyring
# package, accepted only if it is the archive signing key whose fingerprint Ubuntu
# publishes (https://wiki.ubuntu.com/SecurityTeam/FAQ).
UBUNTU_ARCHIVE_KEY=F6ECB3762474EDA9D21B7022871920D1991BC93C
ubuntu_keyring() {
  local keyring="$CACHE/ubuntu-archive-keyring.gpg" work
  if [ ! -s "$keyring" ]; then
    work=$(mktemp -d)
    curl -fsS -o "$work/keyring.deb" \
      "$MIRROR/pool/main/u/ubuntu-keyring/ubuntu-keyring_2021.03.26_all.deb" >&2
    dpkg-deb -x "$work/keyring.deb" "$work/unpacked"
    cp "$work/unpacked/usr/share/keyrings/ubuntu-archive-keyring.gpg" "$keyring.partial"
    rm -rf "$work"
    if ! gpg --show-keys --with-colons "$keyring.partial" 2>/dev/null |
        grep -q "^fpr:::::::::$UBUNTU_ARCHIVE_KEY:"; then
      echo "fresh_machine: the downloaded Ubuntu keyring lacks key $UBUNTU_ARCHIVE_KEY" >&2
      exit 1
    fi
    mv "$keyring.partial" "$keyring"
  fi
  echo "$keyring"
}

# 1. A minimal Debian: debootstrap once per suite, then unpack the cached tarball.
mkdir -p "$CACHE"
if [ "$UBUNTU" = 1 ]; then
  DEBOOTSTRAP_OPTIONS+=(--keyring="$(ubuntu_keyring)")
fi
if [ ! -s "$BASE_TAR" ]; then
  echo "fresh_machine: debootstrap $SUITE (minbase + $BASE_PACKAGES)" >&2
  started=$(seconds)
  debootstrap --variant=minbase "${DEBOOTSTRAP_OPTIONS[@]}" --include="$BASE_PACKAGES" \
    "$SUITE" "$ROOTFS" "$MIRROR" "${DEBOOTSTRAP_SCRIPT[@]}" \
    >"$CACHE/$SUITE-debootstrap.log" 2>&1 ||
    { tail -20 "$CACHE/$SUITE-debootstrap.log" >&2; exit 1; }
  tar -C "$ROOTFS" -cf "$BASE_TAR.partial" . && mv "$BASE_TAR.partial" "$BASE_TAR"
  echo "fresh_machine: debootstrap took $(($(seconds) - started)) s" >&2
else
  tar -C "$ROOTFS" -xf "$BASE_TAR"
fi

# An installed Ubuntu has its updates and universe; debootstrap wrote the release alone.
if [ "$UBUNTU" = 1 ]; then
  cat >"$ROOTFS/etc/apt/sources.list" <<SOURCES
deb $MIRROR $SUITE $SUITE-updates main universe
deb http://security.ubuntu.com/ubuntu $SUITE-security main universe
SOURCES
fi

# mktemp made the folder 0700 (and the tarball keeps that mode for "."): a machine's /
# lets every user through, and the grader's unprivileged user needs that.
chmod 0755 "$ROOTFS"

# The grader makes its users (course-grader, course-grader1, ...) with useradd --system,
# which numbers them down from 999 as it does here: the root's course-grader2 would be
# this machine's course-grader1, and the two graders share one kernel. Each ends a run
# by killing every process of its user's uid, so a suite in the root beside one here
# would kill the other's compiles and runs (SIGKILL). The root's system users are
# numbered from a range of their own instead, one range a suite: two roots of one range
# (a Debian 12 and a Debian 13 root side by side, 2026-12-06) killed each other's runs
# the same way. useradd still makes them when asked.
case "$SUITE" in
  bookworm) UID_BASE=58000 ;;
  trixie) UID_BASE=57000 ;;
  jammy) UID_BASE=56000 ;;
  noble) UID_BASE=55000 ;;
esac
if [ -f "$ROOTFS/etc/login.defs" ]; then
  sed -i -e '/^[#[:space:]]*SYS_UID_M[AI][XN]/d' -e '/^[#[:space:]]*SYS_GID_M[AI][XN]/d' \
    "$ROOTFS/etc/login.defs"
  printf 'SYS_UID_MIN %s\nSYS_UID_MAX %s\nSYS_GID_MIN %s\nSYS_GID_MAX %s\n' \
    "$UID_BASE" "$((UID_BASE + 999))" "$UID_BASE" "$((UID_BASE + 999))" \
    >>"$ROOTFS/etc/login.defs"
fi

# 2. What makes the network work as here: DNS, the CA bundle, apt's and pip's settings.
cp /etc/resolv.conf "$ROOTFS/etc/resolv.conf"
if [ -f /etc/ssl/certs/ca-certificates.crt ]; then
  cp /etc/ssl/certs/ca-certificates.crt "$ROOTFS/etc/ssl/certs/ca-certificates.crt"
fi
for conf in /etc/pip.conf /etc/apt/apt.conf.d/99artifact-registry; do
  [ -f "$conf" ] && cp "$conf" "$ROOTFS$conf"
done
mkdir -p "$ROOTFS/root/.config/pip"
for conf in "$HOME/.pip/pip.conf" "$HOME/.config/pip/pip.conf"; do
  [ -f "$conf" ] && cp "$conf" "$ROOTFS/root/.config/pip/pip.conf"
done
# pip's and the CA bundle's environment variables, as set here (nothing else of ours).
PASS_ENV=(HOME=/root PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin
  LANG=C.UTF-8 TERM=dumb)
while IFS='=' read -r name value; do
  case "$name" in
    PIP_FIND_LINKS) ;;  # a folder of this machine's
    PIP_* | SSL_CERT_FILE | SSL_CERT_DIR | REQUESTS_CA_BUNDLE) PASS_ENV+=("$name=$value") ;;
  esac
done < <(env)

# 3. The checkout, as a clean clone of the committed HEAD.
git clone --quiet --no-local "$REPO" "$ROOTFS/root/course"
git -C "$ROOTFS/root/course" checkout --quiet "$(git -C "$REPO" rev-parse HEAD)"

for mount in proc sys dev dev/pts dev/shm; do
  mkdir -p "$ROOTFS/$mount"
  case "$mount" in
    proc) mount -t proc proc "$ROOTFS/proc" ;;
    sys) mount -t sysfs sys "$ROOTFS/sys" ;;
    dev/shm) mount -t tmpfs shm "$ROOTFS/dev/shm" ;;
    *) mount --bind "/$mount" "$ROOTFS/$mount" ;;
  esac
  MOUNTS+=("$ROOTFS/$mount")
done

if [ "$CACHES" = 1 ]; then
  for kept in "root/.cache:$CACHE/$SUITE-home-cache" \
              "var/cache/apt/archives:$CACHE/$SUITE-apt-archives"; do
    inside="$ROOTFS/${kept%%:*}"
    outside="${kept#*:}"
    mkdir -p "$inside" "$outside"
    # The home cache holds references only its user may read; apt's downloads are
    # fetched by the _apt user.
    case "$inside" in *root/.cache) chmod 0700 "$outside" ;; *) chmod 0755 "$outside" ;; esac
    mount --bind "$outside" "$inside"
    MOUNTS+=("$inside")
  done
  # Debian's apt removes what it downloaded after installing it, unless told to keep it.
  echo 'Binary::apt::APT::Keep-Downloaded-Packages "true";' \
    >"$ROOTFS/etc/apt/apt.conf.d/10keep-downloads"
  echo "fresh_machine: caches kept in $CACHE/$SUITE-home-cache and -apt-archives" >&2
fi

in_root() {
  chroot "$ROOTFS" /usr/bin/env -i "${PASS_ENV[@]}" /bin/bash -c "cd /root/course && $1"
}

python_version=$(chroot "$ROOTFS" python3 -V 2>&1 || true)

if [ -n "$GRADESCOPE" ]; then
  # 4'. Gradescope: the autograder zip and two submissions are made here, from the
  #     checkout; everything else happens in the root as Gradescope would do it.
  host_course() { (cd "$REPO" && ./course "$@"); }
  zip=$(host_course autograder "$GRADESCOPE" --out "$ROOTFS/tmp/autograder.zip" | tail -1)
  starter=$(host_course release "$GRADESCOPE" --out "$ROOTFS/tmp/submissions/starter" | tail -1)
  chapter=$(basename "$(dirname "$(ls -d "$starter"/chapters/*/main.cpp)")")
  mkdir -p "$ROOTFS/tmp/submissions/solution"
  for top in chapters shaders; do
    mkdir -p "$ROOTFS/tmp/submissions/solution/$top"
    cp -r "$REPO/$top/$chapter" "$ROOTFS/tmp/submissions/solution/$top/"
  done
  mkdir -p "$ROOTFS/autograder/source" "$ROOTFS/autograder/submission" \
    "$ROOTFS/autograder/results"
  # Unpacked as Gradescope's unzip does: with each file's mode from the archive.
  chroot "$ROOTFS" python3 -c '
import os, sys, zipfile
with zipfile.ZipFile(sys.argv[1]) as archive:
    for info in archive.infolist():
        path = archive.extract(info, sys.argv[2])
        mode = info.external_attr >> 16 & 0o777
        if mode:
            os.chmod(path, mode)
' /tmp/autograder.zip /autograder/source
  cp "$ROOTFS/autograder/source/run_autograder" "$ROOTFS/autograder/run_autograder"
  summary=()
  status=0
  started=$(seconds)
  if in_root "bash /autograder/source/setup.sh" </dev/null; then result=passed
  else result="FAILED ($?)"; status=1; fi
  took=$(($(seconds) - started))
  summary+=("fresh $SUITE gradescope: setup.sh $result in $((took / 60)) min $((took % 60)) s")
  for submission in solution starter; do
    [ "$status" = 0 ] || break
    rm -rf "$ROOTFS/autograder/submission" "$ROOTFS/autograder/results"
    cp -r "$ROOTFS/tmp/submissions/$submission" "$ROOTFS/autograder/submission"
    mkdir -p "$ROOTFS/autograder/results"
    started=$(seconds)
    in_root "cd /autograder && ./run_autograder" </dev/null || true
    took=$(($(seconds) - started))
    case "$submission" in
      solution) expect=(--expect-fraction-at-least 1.0) ;;
      starter) expect=(--expect-fraction-at-most 0.1) ;;
    esac
    if verdict=$(python3 "$REPO/tools/course_tools/grading/gradescope_results.py" \
        "$ROOTFS/autograder/results/results.json" "${expect[@]}" 2>&1); then
      result=passed
    else
      result=FAILED; status=1
    fi
    summary+=("fresh $SUITE gradescope: $submission $result in $took s: ${verdict##*: }")
  done
  printf '%s\n' "${summary[@]}"
  echo "fresh $SUITE: $python_version"
  exit "$status"
fi

# 4. The README's commands, as written.
test_command="./course test${CHAPTER:+ $CHAPTER}"
summary=()
status=0
# Set-up's exit code when Playwright's own Chromium cannot be downloaded (the Ubuntu
# rows' book check; tools/course_tools/setup/machine_setup.py).
BROWSER_DOWNLOAD_FAILED=9
commands=("./course run")
[ "$RUN_ONLY" = 1 ] || commands+=("$test_command")
for command in "${commands[@]}"; do
  echo "fresh_machine: [$SUITE] $command" >&2
  started=$(seconds)
  log="$ROOTFS/tmp/fresh-command.log"
  set +e
  in_root "$command" </dev/null 2> >(tee "$log" >&2)
  code=$?
  set -e
  sleep 1  # the tee's last lines
  took=$(($(seconds) - started))
  if [ "$code" = 0 ]; then
    result=passed
  elif [ "$UBUNTU" = 1 ] && [ "$code" = "$BROWSER_DOWNLOAD_FAILED" ]; then
    # Not a pass and not the course's failure: the suite never ran. Said as such.
    summary+=("fresh $SUITE: '$command' stopped by set-up (exit $code) after \
$((took / 60)) min $((took % 60)) s: Playwright's Chromium could not be downloaded from \
this machine, so the test layer's set-up ends there and no check ran")
    status=3
    break
  else
    result="FAILED ($code)"; status=1
  fi
  summary+=("fresh $SUITE: '$command' $result in $((took / 60)) min $((took % 60)) s")
  [ "$status" = 0 ] || break
done
mesa=$(chroot "$ROOTFS" dpkg-query -W -f='${Version}' libgl1-mesa-dri 2>/dev/null || echo "?")
printf '%s\n' "${summary[@]}"
echo "fresh $SUITE: $python_version, Mesa $mesa"
exit "$status"
}
