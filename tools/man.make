# Included by every Makefile of the suite that builds a manual page, after
# GRASS's own Make files: GRASS's man-page converter (HTML2MAN of Grass.make,
# used by Html.make's rule for $(MANDIR)/%.1) runs through tools/html2man.py,
# which leaves a page that man shows as ASCII in any locale (why: that
# script's docstring).
HISTO_TOOLS := $(abspath $(dir $(lastword $(MAKEFILE_LIST))))
HTML2MAN = VERSION_NUMBER=$(GRASS_VERSION_NUMBER) $(PYTHON) $(HISTO_TOOLS)/html2man.py \
	$(GISBASE)/utils/g.html2man.py
