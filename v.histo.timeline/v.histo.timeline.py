#!/usr/bin/env python3
############################################################################
#
# MODULE:       v.histo.timeline
# AUTHOR(S):    histo developers
# PURPOSE:      Merges the models of several map epochs of one town into one
#               CityJSON city model over time, every building once with its
#               lifespan, or extracts the town of one year from it
# COPYRIGHT:    (C) 2026 the histo developers
#
#               This program is free software under the GNU General Public
#               License (>=v2). Read the file COPYING that comes with GRASS
#               for details.
#
############################################################################

# %module
# % description: Merges the models of several map epochs of one town into one CityJSON model over time (every building once, with its lifespan), or extracts the town of one year.
# % keyword: vector
# % keyword: building
# % keyword: temporal
# % keyword: CityJSON
# % keyword: histo
# %end
# %option G_OPT_F_INPUT
# % key: models
# % required: no
# % multiple: yes
# % label: CityJSON models of the epochs (v.histo.lod2 output=), one per map
# % description: With years=, in the same order
# % guisection: Epochs
# %end
# %option
# % key: years
# % type: integer
# % required: no
# % multiple: yes
# % description: Year of each model's map (same order as models=)
# % guisection: Epochs
# %end
# %option G_OPT_F_INPUT
# % key: input
# % required: no
# % label: A model over time made by this module, for snapshot=
# % guisection: Epochs
# %end
# %option G_OPT_V_INPUT
# % key: register
# % required: no
# % label: Today's building footprints with their ids and construction years (e.g. the BAG)
# % description: Its buildings still stand: no demolition; their year bounds the construction
# %end
# %option G_OPT_DB_COLUMN
# % key: id_column
# % label: Column of the register's building ids
# % description: Default: the first of identificatie, identifica, pand_id
# %end
# %option G_OPT_DB_COLUMN
# % key: year_column
# % label: Column of the register's construction years
# % description: Default bouwjaar, else oorspronkelijkbouwjaar
# %end
# %option G_OPT_F_OUTPUT
# % description: The model over time (or the snapshot): CityJSON 2.0 file
# %end
# %option
# % key: format
# % type: string
# % options: cityjson,cityjsonseq
# % answer: cityjson
# % description: Output format
# %end
# %option
# % key: snapshot
# % type: integer
# % required: no
# % label: Write the town of this year instead of the whole model
# % description: The latest epoch at or before it, with the buildings the register dates between that epoch and the year
# %end
# %option
# % key: title
# % type: string
# % required: no
# % description: Title of the model (metadata)
# %end
# %option G_OPT_F_OUTPUT
# % key: report
# % required: no
# % description: JSON file with the counts and every conflict between the maps and the register
# %end
# %option G_OPT_F_OUTPUT
# % key: viewer
# % required: no
# % description: HTML page that shows the model in a web browser, offline, with a year slider: the buildings standing in each year
# %end
# %option G_OPT_F_OUTPUT
# % key: gltf
# % required: no
# % description: Binary glTF (.glb) of the town in the last year (or in snapshot=) for Blender, CesiumJS and other 3D tools: one node per building, its attributes in extras
# %end
# %option
# % key: tiles
# % type: string
# % key_desc: name
# % gisprompt: new,dir,dir
# % required: no
# % label: Directory of 3D Tiles 1.1 of the model for CesiumJS and other globes
# % description: tileset.json and a glTF per tile; every version of a building with its id, first and last year and attributes as its metadata; made if missing
# %end
# %flag
# % key: g
# % description: Print the counts in shell script style (key=value)
# %end
# %rules
# % required: models, input
# % exclusive: models, input
# % collective: models, years
# %end

import os
import signal
import sys
import time

# Ctrl-C before the module runs: one error line (grassio.run_main takes over)
signal.signal(signal.SIGINT, lambda *_: sys.exit("ERROR: Interrupted while starting"))

import grass.script as gs  # noqa: E402


def find_core():
    """Put the histo core library on sys.path (installed in etc/histo, or the checkout)."""
    here = os.path.dirname(os.path.realpath(__file__))
    for base in (os.path.join(os.path.dirname(here), "etc", "histo"), os.path.dirname(here)):
        if os.path.isfile(os.path.join(base, "reconstruction", "__init__.py")):
            sys.path.insert(0, base)
            return


def main(options, flags):
    from reconstruction import grassio, timeline

    start = time.perf_counter()
    grassio.check_outputs(options, files=("output", "report", "viewer", "gltf"),
                          inputs={"file": ("models", "input")},
                          directories={"tiles": "tileset.json"})
    config = timeline.read_config(options, flags)
    result = timeline.run(config, grassio.read_table, grassio.doing)
    with grassio.doing("writing '{}'".format(config.output)):
        size = timeline.write(result, config, timeline.report_json(result, config))
    grassio.say(timeline.report(result, config, size, time.perf_counter() - start))
    if config.shell:
        print("\n".join(timeline.shell_counts(result)))
    return 0


if __name__ == "__main__":
    options, flags = gs.parser()
    find_core()
    from reconstruction import grassio

    sys.exit(grassio.run_main(main, options, flags))
