"""What v.histo.lod2 tells its user, as :class:`~reconstruction.core.messages.Message` lists.

:func:`report` gives the messages of a finished run (the model written, the
buildings copied, the -v report's fallbacks and invalid solids);
:func:`validity_lines` the -v report's ``key=value`` lines (standard output).
The other functions give the messages of each step, which
:func:`reconstruction.lod2.run` hands to the script's printer as the step is
done (a progress message before the work it announces), in this order:
:func:`config_messages`, :func:`existing_messages`,
:func:`existing_model_messages`, :func:`map_messages`,
:func:`ground_points_messages`, :func:`matched_heights_messages`,
:func:`plots_messages`, :func:`height_messages`,
:func:`street_messages`, :func:`street_edge_messages`,
:func:`footprint_messages`, :func:`build_messages`, :func:`built_messages`.
"""

import numpy as np

from ..cityjson import existing
from ..cityjson.existing import FAR_ID_MATCH
from ..core import crs
from ..core.messages import note, verbose, warning
from . import street_edges as se
from .config import EXTENSIONS, format_of_name
from .inputs import LOW_BUILDING
from .render import MAX_DRAWN
from .solids.vertex_budget import MAX_ROOF_VERTICES

#: what each format= writes, in the warning on an output name of the other
FORMAT_NAMES = {"cityjson": "one CityJSON document",
                "cityjsonseq": "CityJSONSeq (one JSON object a line)"}
#: the largest ground buffer, in the message on footprints without ground
GROUND_BUFFER = 50.0


def config_messages(config):
    """Warnings about the options (:class:`~reconstruction.lod2.config.Lod2Config`)."""
    out = []
    if config.output.reference_system is None:
        out.append(warning("The location has no EPSG code and crs= is not given: the CityJSON "
                           "file has no reference system"))
    code = crs.epsg_code(config.output.reference_system)
    if code is not None and not crs.same_place(code, config.location_epsg):
        out.append(warning("crs=EPSG:{} is not the location's EPSG:{} (nor a compound system of "
                           "it): the coordinates are written as they are, not reprojected, and "
                           "labelled EPSG:{}".format(code, config.location_epsg, code)))
    named = format_of_name(config.output.path)
    if named is not None and named != config.output.format:
        out.append(warning("output= '{}' ends in {} but format={} writes {}: written as asked "
                           "(give format={} for {})".format(
                               config.output.path, EXTENSIONS[named], config.output.format,
                               FORMAT_NAMES[config.output.format], named,
                               FORMAT_NAMES[named])))
    if config.map_ignored:
        out.append(warning("map= is drawn only in the picture of render= and the page of "
                           "viewer=: ignored"))
    return out


def map_messages(image, footprints):
    """When the map picture of map= (a :class:`~reconstruction.geom.grid.MapImage`)
    is read: a warning when it does not meet the footprints'
    :class:`~reconstruction.geom.grid.Extent` (None: no footprint), as the
    picture would draw the map and the model apart."""
    if footprints is None or image.place.meets(footprints):
        return []
    return [warning("The map of map= ({}) does not overlap the footprints ({}): the picture "
                    "draws them apart (a map of another area or reference system?)".format(
                        image.place.text(), footprints.text()))]


def existing_messages(request):
    """Before the existing model (:class:`~reconstruction.lod2.config.ExistingRequest`) is read."""
    return [note("Reading the existing model '{}'...".format(request.path))]


def existing_model_messages(model, what="existing model",
                            instead="not copied; the footprints they would match are generated"):
    """After the existing model (an :class:`~reconstruction.cityjson.existing.ExistingModel`)
    is read: the broken buildings left out (issue 33), the first few named
    with their problem; ``what`` the model is and what is done ``instead``
    (the earlier epoch's model of previous= gives the same warning)."""
    skipped = model.skipped
    if not skipped:
        return []
    return [warning("{} buildings of the {} '{}' are broken and left out ({}): {}".format(
        len(skipped), what, model.path, instead, existing.broken_named(skipped)))]


def ground_points_messages(config):
    """When the ground points are read: elevation= given too is not used."""
    if config.heights.elevation:
        return [warning("Both ground_points= and elevation= given: the ground comes from the "
                        "points")]
    return []


def matched_heights_messages(count):
    """When ``count`` footprints matched in the existing model give the measured heights."""
    return [note("The {} footprints matched in the existing model take its measured "
                 "heights".format(count))]


def plots_messages(measured):
    """When the plots are read: they are used only where heights are
    ``measured`` (aligned footprints or building points)."""
    return [] if measured else [warning("plots= is used only with aligned= or building_points=")]


def height_messages(report, config):
    """Where the heights came from (a :class:`~reconstruction.lod2.inputs.HeightReport`),
    footprints without ground."""
    h = config.heights
    out = []
    if report.ground_from in ("points", "elevation"):
        what = h.ground_points if report.ground_from == "points" else h.elevation
        out.append(note("Ground from <{}> (percentile {}): {} footprints with the buffer grown "
                        "over a hole".format(what, h.percentile_text, report.ground_grown)))
        if report.ground_missing:
            out.append(warning("{} footprints have no ground point or cell within {:g} m".format(
                report.ground_missing, GROUND_BUFFER)))
    if h.aligned:
        out.append(note("{} of the footprints are aligned footprints with measured heights; {} "
                        "aligned footprints measured".format(report.matched,
                                                             report.aligned_measured)))
        if report.aligned_unmeasured:
            out.append(warning("{} aligned footprints have no measured heights (NULL)".format(
                report.aligned_unmeasured)))
        out.extend(_implausible("aligned footprints", report.aligned_implausible))
    if h.building_points:
        out.append(note("{} footprints have building points".format(report.with_points)))
        out.extend(_implausible("footprints' building points", report.points_implausible))
        if report.points_measured and 2 * report.points_low > report.points_measured:
            out.append(warning("The building points of <{}> stand less than {:g} m above the "
                               "ground on {} of {} footprints (median {:.2f} m): are they ground "
                               "points?".format(h.building_points, LOW_BUILDING,
                                                report.points_low, report.points_measured,
                                                report.points_median_top)))
    out.append(verbose("Height sources: {}".format(
        ", ".join("{} {}".format(v, k) for k, v in report.sources.items()))))
    return out


def _implausible(what, problems):
    """One warning per reason of measured heights not used as implausible (reason -> count)."""
    return [warning("{} {} have implausible measured heights ({}): not used, their heights "
                    "inferred as for footprints without".format(n, what, reason))
            for reason, n in problems.items()]


def street_messages(streets):
    """About the street options (a :class:`~reconstruction.lod2.config.StreetConfig`)."""
    if streets.classes_ignored:
        return [warning("street_classes= is used only with streets=")]
    return []


def street_edge_messages(edges):
    """How the street edges (:class:`~reconstruction.lod2.street_edges.StreetEdges`)
    were chosen: the count of each case."""
    n = np.bincount(edges.case, minlength=6)
    return [note("Street edges: {} one unshared edge, {} from a neighbour, {} by vote, {} "
                 "shortest, {} facing the streets map; {} enclosed (no street edge)".format(
                     n[se.ONE_FREE], n[se.FROM_NEIGHBOUR], n[se.VOTE], n[se.SHORTEST],
                     n[se.STREETS], n[se.ENCLOSED]))]


def footprint_messages(report, config):
    """The footprints left out or changed before building (a
    :class:`~reconstruction.lod2.stage.Lod2Report` of prepare)."""
    out = []
    if report.bad_eaves:
        out.append(warning("{} footprints with NULL, zero or negative eaves height are left "
                           "out".format(report.bad_eaves)))
    if report.bad_attic:
        out.append(warning("{} footprints with NULL or negative roof height get a flat "
                           "roof".format(report.bad_attic)))
    if report.bad_ground:
        out.append(warning("{} footprints with NULL ground elevation are set on ground={}".format(
            report.bad_ground, config.heights.ground_text)))
    if report.holes_filled:
        out.append(warning("{} holes (inner courtyards) in footprints are filled".format(
            report.holes_filled)))
    if report.left_out:
        reasons = ", ".join("{} {}".format(v, k) for k, v in report.left_out_reasons.items())
        out.append(warning("{} footprints or parts of footprints are left out (empty or "
                           "degenerate: {})".format(report.left_out, reasons or "no geometry")))
    return out


def build_messages(rings):
    """Before ``rings`` solids are built."""
    return [note("Building {} solids...".format(rings))] if rings else []


def built_messages(report):
    """The buildings left out or simpler than requested (a
    :class:`~reconstruction.lod2.stage.Lod2Report` of build)."""
    out = []
    if report.dropped:
        out.append(warning("{} footprints gave no valid solid, even flat, and are left "
                           "out".format(report.dropped)))
    if report.fell_back:
        out.append(warning("{} roofs fell back to a simpler type to stay valid".format(
            report.fell_back)))
    if report.by_rule:
        out.append(verbose("{} roofs changed type by the roof rules (no free street end for a "
                           "stepped facade or a gable)".format(report.by_rule)))
    if report.simplified:
        out.append(note("{} footprints of more than {} vertices got their pitched roof on a "
                        "simplified outline".format(report.simplified, MAX_ROOF_VERTICES)))
    return out


def previous_messages(path, report):
    """What the earlier epoch's model (previous=) gave: the buildings kept, and those of
    an earlier identity built anew (:class:`~reconstruction.lod2.previous.PreviousReport`)."""
    out = [note("Earlier epoch '{}': {} of {} footprints with a building identity keep their "
                "building".format(path, report.kept, report.footprints))]
    if report.measured or report.reshaped:
        out.append(note("Built anew with their earlier roof type: {} measured otherwise in "
                        "this epoch, {} on another outline".format(report.measured,
                                                                    report.reshaped)))
    if report.new:
        out.append(verbose("{} footprints are new buildings (not in the earlier "
                           "model)".format(report.new)))
    return out


def report(result, config):
    """The messages of a finished run (a :class:`~reconstruction.lod2.pipeline.Lod2Run`):
    the buildings written (by roof type), those copied from the existing
    model, the picture; with -v the roofs that fell back and the invalid solids."""
    written, counts = result.written, result.model.roof_counts()
    out = [note("{} buildings written to '{}': {}".format(
        written.generated + written.copied + written.kept, config.output.path,
        ", ".join("{} {}".format(v, k) for k, v in counts.items() if v)))]
    if written.match is not None:
        m = written.match
        out.append(note("{} of {} aligned footprints copied from the existing model ({} matched "
                        "by id, {} by geometry)".format(written.copied, written.candidates,
                                                        m.by_id, m.by_geometry)))
        if m.ids_not_found:
            out.append(warning("{} building ids matched no object of the existing model (tried "
                               "by geometry)".format(m.ids_not_found)))
        if m.duplicate_ids:
            out.append(warning("{} aligned footprints have the building id of an earlier "
                               "footprint (e.g. {}): the building is copied once, for the "
                               "first; {} of them are generated".format(
                                   m.duplicate_ids, ", ".join(m.duplicate_examples),
                                   m.duplicates_unmatched)))
        if m.far_ids:
            out.append(warning("{} building ids name buildings of the existing model more than "
                               "{:.0f} m from their footprints (e.g. {}, {:.0f} m away): not "
                               "copied, tried by geometry".format(
                                   m.far_ids, FAR_ID_MATCH, m.far_example[0],
                                   m.far_example[1])))
        if m.unmatched:
            out.append(warning("{} aligned footprints matched no building of the existing model "
                               "and are generated".format(m.unmatched)))
        if written.copy.lod_fallback:
            out.append(warning("{} copied buildings have none of the LoDs of existing_lod= and "
                               "are copied at their highest".format(written.copy.lod_fallback)))
        if written.copy.skipped_geometries:
            out.append(warning("{} geometries of copied buildings (templates or unknown types) "
                               "are left out".format(written.copy.skipped_geometries)))
    if written.kept:
        out.append(note("{} buildings kept from the earlier epoch's model, as they were".format(
            written.kept)))
    if written.rendered:
        out.append(note("Picture written to '{}'".format(written.rendered)))
        if written.drawn is not None:
            out.append(note("The picture draws the buildings of the {} footprints nearest the "
                            "middle of the model: a picture draws at most {}".format(
                                written.drawn, MAX_DRAWN)))
    if result.invalid is not None:
        for f in result.model.report.fallbacks:
            out.append(note("Footprint cat {}: {} roof invalid ({}), fell back".format(
                f.footprint, f.kind, f.reason)))
        out.extend(note("Invalid solid: {}".format(r)) for r in result.invalid if r is not None)
        out.extend(note("Invalid copied solid {}: {}".format(label, r))
                   for label, r in written.copied_checked or () if r is not None)
        if written.copied_unchecked:
            out.append(note("{} copied solids have inner shells or faces with holes and are not "
                            "checked".format(written.copied_unchecked)))
    return out



def drawing_messages(path):
    """Said before the picture is drawn (seconds for a large model)."""
    return [verbose("Drawing the picture '{}'...".format(path))]

def validity_lines(result):
    """The -v report's lines (standard output): counts and percent valid
    (of the generated solids, one per footprint built, and of the copied
    Solids checked), fallbacks, dropped and simplified buildings, the copied
    solids checked and valid, buildings per roof type; none without -v."""
    if result.invalid is None:
        return []
    model, check = result.model, result.invalid
    copied = [r for _, r in result.written.copied_checked or ()]
    valid = sum(r is None for r in check) + sum(r is None for r in copied)
    total = model.report.rings + len(copied)
    lines = ["solids={}".format(total), "valid={}".format(valid),
             "percent_valid={:.2f}".format(100.0 * valid / total if total else 100.0),
             "fallbacks={}".format(len(model.report.fallbacks)),
             "dropped={}".format(model.report.dropped),
             "simplified={}".format(model.report.simplified),
             "copied_solids={}".format(len(copied)),
             "copied_valid={}".format(sum(r is None for r in copied))]
    return lines + ["roof_{}={}".format(k, v) for k, v in model.roof_counts().items()]
