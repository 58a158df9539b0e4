"""Import the Delft 1961 subset into the current GRASS mapset (demo/delft_1961.sh, step 1).

    python3 demo/delft_import.py SHARED_DATA [FOUND_JSON]

SHARED_DATA is the shared data folder (../shared/data from the checkout).
FOUND_JSON (optional) gets the categories in <current> of the thesis's
aligned footprints (keys thesis1961, thesis1880), for the report.
Makes: the map bands delft.red, .green, .blue; delft_training (training
points), delft_gt_points and delft_gt_polygons (ground truth); thesis_raw_plots
(the thesis's raw building plots, for the report); current (the
current footprints with their years built and, where the footprint is one of
the thesis's aligned 1880 footprints, its 3D BAG heights), as
testsuite/histo_testing.py's import_delft_alignment builds them. Nothing is
written outside the mapset.
"""

import json
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def main(shared_data, found_json=None):
    for path in (ROOT, os.path.join(ROOT, "testsuite")):
        if path not in sys.path:
            sys.path.insert(0, path)
    import grass.script as gs

    from histo_testing import import_delft_alignment

    folder = os.path.join(shared_data, "delft_1961_subset", "input")
    if not os.path.isfile(os.path.join(folder, "delft_1961.tif")):
        gs.fatal("No Delft 1961 subset in <{}>: give the shared data folder (e.g. "
                 "../shared/data, as an absolute path or relative to where the script "
                 "runs)".format(os.path.abspath(shared_data)))
    gs.run_command("r.in.gdal", input=os.path.join(folder, "delft_1961.tif"), output="delft",
                   flags="o", quiet=True, overwrite=True)
    for name, output in (("training_points_delft_1961", "delft_training"),
                         ("ground_truth_delft_1961", "delft_gt_points"),
                         ("ground_truth_generalized_delft_1961", "delft_gt_polygons")):
        gs.run_command("v.in.ogr", input=os.path.join(folder, name + ".shp"), output=output,
                       flags="o", quiet=True, overwrite=True)
    # the thesis's raw plots (its classification, before the generalisation): the
    # report measures how far their outlines lie outside the digitised plots
    gs.run_command("v.in.ogr", input=os.path.join(
        shared_data, "delft_1961_subset", "thesis_output", "raw_building_plots_delft_1961.shp"),
        output="thesis_raw_plots", flags="o", quiet=True, overwrite=True)
    found = import_delft_alignment(shared_data, heights=True)
    print("current footprints with a year built: {}, of them thesis 1961 aligned: {}, with "
          "1880 3D BAG heights: {}".format(len(found["years"]), len(found["thesis1961"]),
                                          len(found["thesis1880"])))
    if found_json:
        with open(found_json, "w") as f:
            json.dump({k: sorted(int(c) for c in found[k])
                       for k in ("thesis1961", "thesis1880")}, f)


if __name__ == "__main__":
    main(*sys.argv[1:])
