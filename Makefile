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
	v.histo.lod2

MODULE_TOPDIR ?= $(shell grass --config path 2>/dev/null)

# GRASS's Make system only exists once grass-dev is installed: the project
# targets below install it first and then call make again.
ifneq ($(wildcard $(MODULE_TOPDIR)/include/Make/Dir.make),)
include $(MODULE_TOPDIR)/include/Make/Dir.make
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
HISTO_PYTHON ?= python3
DIST ?= $(CURDIR)/dist
STAMPS := $(CURDIR)/.stamps
DEMO_DIR ?= $(CURDIR)/demo-output
PYTEST_ARGS ?=

.PHONY: deps build test demo bench user-install clean-dist

# Debian packages: GRASS 8.2 (core + Make system) and what g.extension wants.
$(STAMPS)/apt:
	@mkdir -p $(STAMPS)
	@if command -v grass >/dev/null 2>&1 && [ -f "$$(grass --config path)/include/Make/Dir.make" ] \
	    && command -v svn >/dev/null 2>&1; then \
	  echo "GRASS GIS and its Make system are installed"; \
	else \
	  apt-get update -q && DEBIAN_FRONTEND=noninteractive apt-get install -y -q \
	    grass-core grass-dev subversion make gcc python3-pip; \
	fi
	@touch $@

# Python packages, pinned, into the python3 that GRASS scripts run with
# (#!/usr/bin/env python3). Debian's own python3 is "externally managed".
$(STAMPS)/pip: requirements.txt | $(STAMPS)/apt
	PIP_BREAK_SYSTEM_PACKAGES=1 $(HISTO_PYTHON) -m pip install -q --disable-pip-version-check -r requirements.txt
	@touch $@

deps: $(STAMPS)/apt $(STAMPS)/pip

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
	  PATH=$$(grass --config path)/bin:$$PATH PYTHONPATH=$$(grass --config python_path) $(DIST)/scripts/$$m --interface-description \
	    > /dev/null || { echo "module $$m does not answer --interface-description"; exit 1; }; \
	done
	@echo "histo built into $(DIST)"

test: build
	$(HISTO_PYTHON) -m pytest $(PYTEST_ARGS)

demo: build
	HISTO_DIST=$(DIST) bash demo/run_demo.sh "$(DEMO_DIR)"

bench: build
	bash testsuite/benchmarks/run_all.sh

# Install for the current user, through g.extension from this checkout
# (offline), into $$GRASS_ADDON_BASE or ~/.grass8/addons.
user-install: deps
	bash tools/g_extension_install.sh "$(CURDIR)"

clean-dist:
	rm -rf $(DIST) $(STAMPS)
