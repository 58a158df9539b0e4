#!/usr/bin/env python3
############################################################################
#
# MODULE:       v.histo.generalize
# AUTHOR(S):    histo developers
# PURPOSE:      (placeholder: filled by the module's issue)
# COPYRIGHT:    (C) 2026 the histo developers
#
#               This program is free software under the GNU General Public
#               License (>=v2). Read the file COPYING that comes with GRASS
#               for details.
#
############################################################################

# %module
# % description: Placeholder of the histo suite (not implemented yet).
# % keywords: histo
# %end

import os
import sys

import grass.script as gs


def find_core():
    """Put the histo core library on sys.path (installed in etc/histo, or the checkout)."""
    here = os.path.dirname(os.path.realpath(__file__))
    for base in (os.path.join(os.path.dirname(here), "etc", "histo"), os.path.dirname(here)):
        if os.path.isfile(os.path.join(base, "reconstruction", "__init__.py")):
            sys.path.insert(0, base)
            return


def main():
    gs.fatal(_("v.histo.generalize is not implemented yet"))


if __name__ == "__main__":
    gs.parser()
    find_core()
    sys.exit(main())
