# histo: a GRASS GIS 8 addon suite that reconstructs LoD2 city models from
# scanned historical maps.
#
# Two kinds of targets live here:
#  - the GRASS addon build (default, install), driven by GRASS's own Make
#    system exactly as g.extension expects it;
#  - the project's own commands (deps, build, test, demo, bench), which set up
#    everything they need on a fresh Debian machine first.

# The toolbox's own page (histo.html). Written with `override` on purpose:
# g.extension lists every Makefile line starting with "PGM" as a module, and
# the toolbox page is not a module.
override PGM := histo

# Library first, then the modules (explicit: a wildcard would pick up testsuite/).
SUBDIRS = \
	reconstruction \
	r.histo.classify \
	v.histo.generalize \
	v.histo.align \
	v.histo.subdivide \
	v.histo.lod2 \
	v.histo.timeline

MODULE_TOPDIR ?= $(shell grass --config path 2>/dev/null)

# GRASS's Make system only exists once grass-dev is installed: the project
# targets below install it first and then call make again.
ifneq ($(wildcard $(MODULE_TOPDIR)/include/Make/Dir.make),)
include $(MODULE_TOPDIR)/include/Make/Dir.make
# the manual pages' man versions in ASCII (tools/html2man.py says why)
include tools/man.make
endif

default: parsubdirs htmldir

# g.extension calls `make install` with INST_DIR and ARCH_DISTDIR on the
# command line: that is GRASS's install. A plain `make install` by a user
# installs the suite for the current user through g.extension.
ifeq ($(origin INST_DIR),command line)
install: installsubdirs
	$(INSTALL_DATA) $(HTMLDIR)/histo.html $(INST_DIR)/docs/html/
else
install: user-install
endif

# ---------------------------------------------------------------------------
# Project commands
# ---------------------------------------------------------------------------
# Python: a virtual environment (VENV) holding the pinned packages of
# requirements.txt (their dependencies pinned by constraints.txt), made from
# Debian's python3, the interpreter GRASS itself runs with, by tools/venv.sh.
# It lives outside the checkout because g.extension copies the whole checkout
# it installs from (and reads every .py file in it). GRASS's Python library
# (grass.script) is not in it: a GRASS session puts it on PYTHONPATH. The
# suite's modules start with `#!/usr/bin/env python3`, so every project
# command runs with $(VENV)/bin first on the PATH; a user's own GRASS session
# does the same through ~/.grass8/bashrc (README, "Install in GRASS GIS").
SYSTEM_PYTHON ?= $(firstword $(wildcard /usr/bin/python3) python3)
VENV ?= $(HOME)/.local/share/histo/venv
HISTO_PYTHON := $(VENV)/bin/python3
VENV_ENV := PATH="$(VENV)/bin:$$PATH"
DIST ?= $(CURDIR)/dist
DEMO_DIR ?= $(CURDIR)/demo-output
PYTEST_ARGS ?=
# Khronos's glTF validator (npm, no dependencies of its own), which the tests
# of the glTF export run on a written file, and CesiumJS, which the tests of
# the 3D Tiles (tiles=) load in headless chromium from a server on 127.0.0.1
# (its built files, Build/Cesium: 23 MB; the package 133 MB with its
# dependencies; it asks for Node.js 22 but only its build tools need it);
# in NODE_DIR, outside the checkout like the venv. Debian's npm is installed
# first where no npm is found (a machine that has Node.js with its own npm
# keeps it).
NODE_DIR ?= $(HOME)/.local/share/histo/node
GLTF_VALIDATOR := gltf-validator@2.0.0-dev.3.10
CESIUM := cesium@1.145.0
NODE_PACKAGES := $(GLTF_VALIDATOR) $(CESIUM)
# GRASS 8.2 (core + Make system), what g.extension wants (make, gcc, svn),
# venv for Debian's python3, man for `g.manual -m`; the run-time libraries of
# val3dity (../shared/tools/val3dity, the tests' oracle of valid solids); EGL
# and Mesa's drivers for pyvista's off-screen rendering without a display;
# chromium, the real browser the HTML 3D viewer's tests drive headless
# through Playwright (never a browser Playwright downloads), and libjs-three
# (three.js r111), which the viewer inlines so it opens from file:// offline.
# Redis (redis-server) and curl for the map series' actinia service, zip (actinia
# packs a job's exported files with /usr/bin/zip: without it every sheet failed
# on a fresh machine), python3-dev for the uWSGI build of actinia's venv
# (section "actinia" below); defined before DEBIAN_PACKAGES, whose := expands
# it at once.
ACTINIA_DEBIAN_PACKAGES := redis-server curl zip python3-dev
DEBIAN_PACKAGES := grass-core grass-dev subversion make gcc python3-venv man-db \
	libboost-filesystem1.74.0 libmpfr6 libgmp10 libgeos-c1v5 libegl1 libgl1-mesa-dri \
	chromium libjs-three $(ACTINIA_DEBIAN_PACKAGES)

.PHONY: deps debian-packages venv node-tools actinia build test demo bench user-install clean-dist

# Installs only what is missing (apt needs root; on a machine that has it all
# nothing is asked for).
debian-packages:
	@missing=$$(for p in $(DEBIAN_PACKAGES); do \
	  dpkg-query -W -f='$${Status}\n' $$p 2>/dev/null | grep -q '^install ok installed$$' || echo $$p; \
	done); \
	if [ -n "$$missing" ]; then \
	  echo "installing Debian packages:" $$missing; \
	  apt-get update -q && DEBIAN_FRONTEND=noninteractive apt-get install -y -q $$missing; \
	fi

venv: debian-packages
	@bash tools/venv.sh "$(VENV)" "$(SYSTEM_PYTHON)"

node-tools:
	@if ! command -v npm > /dev/null; then \
	  echo "installing Debian's npm (for $(NODE_PACKAGES))"; \
	  apt-get update -q && DEBIAN_FRONTEND=noninteractive apt-get install -y -q npm; \
	fi
	@if [ "$$(cat $(NODE_DIR)/.histo-node 2>/dev/null)" != "$(NODE_PACKAGES)" ]; then \
	  echo "installing $(NODE_PACKAGES) into $(NODE_DIR)"; mkdir -p $(NODE_DIR) && \
	  flock $(NODE_DIR).lock npm install -q --prefix $(NODE_DIR) --no-save --no-audit --no-fund \
	    --engine-strict=false $(NODE_PACKAGES) && echo "$(NODE_PACKAGES)" > $(NODE_DIR)/.histo-node; \
	fi

deps: debian-packages venv node-tools actinia

# Stage the built suite in dist/ (never the system tree); fail on any error
# that GRASS's Dir.make would only log.
build: deps
	@rm -rf $(DIST) && mkdir -p $(DIST)/strings
	@$(MAKE) --no-print-directory MODULE_TOPDIR=$$(grass --config path) \
	  ARCH_DISTDIR=$(DIST) ERRORLOG=$(DIST)/error.log STRINGDIR=$(DIST)/strings \
	  GISBASE=$$(grass --config path) default > $(DIST)/build.log 2>&1 \
	  || { cat $(DIST)/build.log; exit 1; }
	@if [ -s $(DIST)/error.log ]; then cat $(DIST)/build.log $(DIST)/error.log; echo "build failed"; exit 1; fi
	@for m in $(filter-out reconstruction,$(SUBDIRS)); do \
	  test -x $(DIST)/scripts/$$m || { echo "module $$m was not built"; exit 1; }; \
	  test -s $(DIST)/docs/html/$$m.html || { echo "man page of $$m was not built"; exit 1; }; \
	  GISRC=$$(grass --config path)/demolocation/.grassrc82 GISBASE=$$(grass --config path) \
	  PATH=$$(grass --config path)/bin:$(VENV)/bin:$$PATH PYTHONPATH=$$(grass --config python_path) \
	  $(DIST)/scripts/$$m --interface-description \
	    > /dev/null || { echo "module $$m does not answer --interface-description"; exit 1; }; \
	done
	@echo "histo built into $(DIST)"

test: build
	$(VENV_ENV) HISTO_DIST=$(DIST) HISTO_STRICT_SKIPS=1 $(HISTO_PYTHON) -m pytest $(PYTEST_ARGS)

demo: build
	$(VENV_ENV) HISTO_DIST=$(DIST) bash demo/run_demo.sh "$(DEMO_DIR)"

bench: build
	$(VENV_ENV) HISTO_DIST=$(DIST) bash testsuite/benchmarks/run_all.sh

# Install for the current user, through g.extension from this checkout
# (offline), into $$GRASS_ADDON_BASE or ~/.grass8/addons, and tell GRASS
# sessions to run the modules with the venv.
user-install: deps
	HISTO_VENV=$(VENV) bash tools/g_extension_install.sh "$(CURDIR)"

clean-dist:
	rm -rf $(DIST) $(CURDIR)/.stamps

# ---------------------------------------------------------------------------
# actinia: a map series on a pool of GRASS workers (issue 30)
# ---------------------------------------------------------------------------
# actinia-core 4.14.1, the last release of the 4.x line (the line built on
# GRASS 8.2, whose API speaks of locations; 5.x is built on GRASS 8.3, 6.x and
# 7.x on 8.4), in a venv of its own (its dependencies, pinned by
# tools/actinia/constraints.txt, would clash with the suite's pins), made from
# Debian's python3 like the suite's. Redis (redis-server), curl and zip from
# Debian (python3-dev: pip builds uWSGI, which actinia runs under, from source).
# tools/actinia/service.sh starts and stops them; tools/histo_series.py
# runs a series through them (README, "A map series on actinia").
ACTINIA_VENV ?= $(HOME)/.local/share/histo/actinia-venv
ACTINIA_CORE := actinia-core==4.14.1

actinia: debian-packages
	@wanted="$(ACTINIA_CORE) $$(cat tools/actinia/constraints.txt)"; \
	if [ "$$(cat $(ACTINIA_VENV)/.histo-actinia 2>/dev/null)" != "$$wanted" ]; then \
	  echo "installing $(ACTINIA_CORE) into $(ACTINIA_VENV)"; \
	  rm -rf $(ACTINIA_VENV) && $(SYSTEM_PYTHON) -m venv $(ACTINIA_VENV) && \
	  $(ACTINIA_VENV)/bin/python3 -m pip install -q --disable-pip-version-check \
	    $(ACTINIA_CORE) -c tools/actinia/constraints.txt && \
	  printf '%s' "$$wanted" > $(ACTINIA_VENV)/.histo-actinia || { rm -rf $(ACTINIA_VENV); exit 1; }; \
	fi
