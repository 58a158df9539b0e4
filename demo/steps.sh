# Helpers and stage functions shared by the chain scripts (demo/chain.sh,
# demo/delft_1961.sh, demo/brussels_1924.sh); sourced, not run. They need a
# GRASS session.
#
# The stage functions run one module of the chain each, when it is
# implemented and its input exists (an earlier stage may have been skipped):
# the map names between the stages (plots, aligned, unmatched, footprints)
# and the report files are the same in every chain; a chain's own parameters
# follow as OPTION=VALUE arguments, passed to the module as they are. They
# read the caller's variables OUT (the output folder), SEED and, when set,
# TIMES (a file that gets each stage's wall time, see timed), NPROCS (the
# classification's processes, default 2) and ALPHA, DISTANCE, ANGLE (the
# generalisation's, default the thesis's 12, 5, 180).

# Run a stage only when its module is installed and implemented.
implemented() {
    if ! command -v "$1" > /dev/null 2>&1; then
        echo "--- skip $1: not installed"
        return 1
    fi
    if "$1" --interface-description 2> /dev/null | grep -q "Placeholder"; then
        echo "--- skip $1: not implemented yet"
        return 1
    fi
    echo "--- $1 (at ${SECONDS} s)"
}

# The input of a stage must exist (an earlier stage may have been skipped).
have() {  # have raster|vector NAME
    if [ -n "$(g.list type="$1" pattern="$2")" ]; then return 0; fi
    echo "--- skip the next stage: its input $1 map <$2> was not made"
    return 1
}

# Run a command and append its wall time to a file: timed FILE STAGE COMMAND...
# (a line "STAGE MILLISECONDS"); the command's output passes through.
timed() {
    local file=$1 stage=$2 start
    shift 2
    start=$(date +%s%N)
    "$@"
    echo "$stage $(( ($(date +%s%N) - start) / 1000000 ))" >> "$file"
}

# The output folder OUT made and made absolute; TIMES=OUT/times.txt, emptied
# (every stage of the run is timed into it): start_run
start_run() {
    mkdir -p "$OUT"
    OUT=$(cd "$OUT" && pwd)
    TIMES=$OUT/times.txt
    : > "$TIMES"
}

# A stage's command, printed on standard error ("--- run: COMMAND", so a log
# shows what ran, also where the module's output goes to a file) and timed
# into $TIMES when the caller set it: stage STAGE COMMAND...
stage() {
    echo "--- run: ${*:2}" >&2
    if [ -n "${TIMES:-}" ]; then
        timed "$TIMES" "$@"
    else
        shift
        "$@"
    fi
}

# The pixels' classes from the training points:
# classify_stage RED,GREEN,BLUE TRAINING CLASSES [OPTION=VALUE...]
classify_stage() {
    local rgb=$1 training=$2 classes=$3
    shift 3
    implemented r.histo.classify || return 0
    stage classify r.histo.classify input="$rgb" training="$training" output="$classes" \
        nprocs="${NPROCS:-2}" seed="$SEED" "$@"
}

# Generalised building plots <plots> from one class of the classified map,
# by default with the thesis's alpha 12, distance 5 and angle 180 (its Table B.3)
# and tolerance 1, in metres, given: the module's defaults follow the cell size;
# OUT/generalize.json and OUT/generalize_metrics.csv:
# generalize_stage CLASSES BUILDING_CLASS [OPTION=VALUE...] (e.g. gt_points=, gt_polygons=)
generalize_stage() {
    local classes=$1 class=$2
    shift 2
    have raster "$classes" && implemented v.histo.generalize || return 0
    stage generalize v.histo.generalize raster="$classes" class="$class" output=plots \
        alpha="${ALPHA:-12}" distance="${DISTANCE:-5}" angle="${ANGLE:-180}" \
        tolerance="${TOLERANCE:-1}" \
        metrics="$OUT/generalize_metrics.csv" \
        report="$OUT/generalize.json" "$@"
}

# Today's footprints that stood at the map's date, matched with <plots>:
# <aligned>, <unmatched>, OUT/align.json: align_stage FOOTPRINTS YEAR [OPTION=VALUE...]
align_stage() {
    local footprints=$1 year=$2
    shift 2
    have vector plots && have vector "$footprints" && implemented v.histo.align || return 0
    stage align v.histo.align input=plots footprints="$footprints" year="$year" \
        output=aligned unmatched=unmatched report="$OUT/align.json" "$@"
}

# Building footprints <footprints> inside <plots>, the aligned ones (when
# <aligned> exists) as they are: subdivide_stage [OPTION=VALUE...]
subdivide_stage() {
    have vector plots && implemented v.histo.subdivide || return 0
    local aligned=
    if [ -n "$(g.list type=vector pattern=aligned)" ]; then aligned=aligned=aligned; fi
    stage subdivide v.histo.subdivide input=plots output=footprints seed="$SEED" $aligned "$@"
}

# LoD2 buildings of <footprints>: OUT/model.city.json, its -v figures in
# OUT/lod2.txt (printed too). Heights from <aligned> (and <plots>) when there
# are aligned footprints, else drawn from the ranges HEIGHT and ATTIC; street
# edges from the classes STREET_CLASSES of the raster STREETS when it exists
# ("-" for none): lod2_stage HEIGHT ATTIC STREETS STREET_CLASSES [OPTION=VALUE...]
lod2_stage() {
    local heights="height=$1 attic=$2" streets=
    if [ -n "$(g.list type=raster pattern="$3")" ]; then
        streets="streets=$3 street_classes=$4"
    fi
    shift 4
    have vector footprints && implemented v.histo.lod2 || return 0
    if [ -n "$(g.list type=vector pattern=aligned)" ]; then
        heights="aligned=aligned plots=plots"
    fi
    stage lod2 v.histo.lod2 -v input=footprints output="$OUT/model.city.json" $heights $streets \
        seed="$SEED" "$@" > "$OUT/lod2.txt"
    cat "$OUT/lod2.txt"
}
