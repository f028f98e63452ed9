# One-command set-up and test.  `make test` / `make run` / `make bench` create .venv,
# install the project with its test extra and the system libraries the viewer and the
# suite load (OSMesa for headless rendering, Xvfb and the xcb libraries of PyQt5's
# wheel for the real window, Debian's chromium for the browser view's tests).  Every step is skipped when already done.

PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed
SYSTEM_PKGS := libosmesa6 libgl1 xvfb xauth libxcb-icccm4 libxcb-image0 libxcb-keysyms1 \
	libxcb-render-util0 libxcb-xinerama0 libxcb-xkb1 libxkbcommon-x11-0 libxcb-shape0 \
	libxcb-randr0 libxcb-xfixes0 libfontconfig1 libdbus-1-3 fonts-dejavu-core \
	chromium
XVFB := xvfb-run -a -s "-screen 0 1280x1024x24"

.PHONY: test test-full run bench pictures setup system-deps clean

# The default suite: every test but the slow parts of the robot and start sweeps.  Its
# pytest runs go side by side: the headless tests (OSMesa) in front, in three pytest-xdist
# workers (a test file stays on one worker, its module fixtures built once; the longest
# files first, in tests/conftest.py's order, not reordered by xdist; a third worker
# on two cores fills the time the others wait for a kernel another process compiles or
# for the browser: 235-244 s on a fresh clone against 238-264 s with two, before the cycle collector was tuned), the
# real-window tests (Xvfb, mostly waiting for the window) behind, their report printed after
# the headless one (only tests/qt is collected for them: every window test lives there,
# tests/test_suite_layout.py checks).  A kernel is compiled by one process only (tests/compile_lock.py).
# NumPy's OpenBLAS gets one thread in each: three processes share two cores, and idle
# OpenBLAS threads spin (warm headless run: 159 s of CPU instead of 171 s).
# Python writes its bytecode caches even where the environment says not to
# (PYTHONDONTWRITEBYTECODE): four processes and the suite's subprocesses would otherwise
# each compile the same sources and rewrite the same test modules' asserts again.
# Fails when either fails.
test: setup
	@export OPENBLAS_NUM_THREADS=1; unset PYTHONDONTWRITEBYTECODE; log=$$(mktemp); \
	$(XVFB) $(PY) -m pytest -q -m window -p no:cacheprovider tests/qt >$$log 2>&1 & window=$$!; \
	trap 'kill $$window 2>/dev/null; rm -f $$log' INT TERM; \
	echo "headless tests (OSMesa, three workers); the window tests run meanwhile under xvfb-run"; \
	PYOPENGL_PLATFORM=osmesa $(PY) -m pytest -q -n 3 --dist loadfile --no-loadscope-reorder; headless=$$?; \
	wait $$window; windowed=$$?; \
	echo "window tests (xvfb-run, pytest -m window tests/qt):"; cat $$log; rm -f $$log; \
	test $$headless -eq 0 && test $$windowed -eq 0

# Everything, the full sweeps included.
test-full: setup
	PYOPENGL_PLATFORM=osmesa $(PY) -m pytest -q -m "not window"
	$(XVFB) $(PY) -m pytest -q -m window tests/qt

# `make run ARGS="--robot ur5 --demo pick"`: the window with those arguments.
run: setup
	$(PY) simulator.py $(ARGS)

bench: setup
	PYOPENGL_PLATFORM=osmesa $(PY) benchmarks/bench.py

# Re-render every picture of docs/ with the command written next to it in the docs.
pictures: setup
	PYOPENGL_PLATFORM=osmesa $(PY) docs/pictures.py
	$(XVFB) $(PY) docs/window_picture.py docs/window.png

setup: system-deps $(STAMP)

$(STAMP): pyproject.toml
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install -q --disable-pip-version-check -e '.[test]'
	rm -rf build *.egg-info  # setuptools' build droppings: the source tree stays as cloned
	touch $(STAMP)

# Installs missing Debian packages with apt-get as root or through passwordless sudo;
# otherwise prints the one command to run and stops.
system-deps:
	@missing=$$(for p in $(SYSTEM_PKGS); do \
		dpkg-query -W -f='$${Status}\n' $$p 2>/dev/null | grep -q '^install ok installed' || echo $$p; \
	done); \
	if [ -z "$$missing" ]; then exit 0; fi; \
	if [ "$$(id -u)" = 0 ]; then SUDO=; \
	elif sudo -n true 2>/dev/null; then SUDO=sudo; \
	else echo "Missing system packages. Run: sudo apt-get install -y" $$missing; exit 1; fi; \
	echo "Installing system packages:" $$missing; \
	$$SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq $$missing >/dev/null

clean:
	rm -rf $(VENV) build *.egg-info .pytest_cache
