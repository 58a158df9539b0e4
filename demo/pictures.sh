# One picture per stage of the histo chain, drawn with GRASS's display
# modules and the cairo driver (no display needed); sourced by the chain
# scripts (demo/chain.sh), not run. Needs a GRASS session.
#
#   stage_pictures OUT PREFIX [WIDTH]
#
# writes into the folder OUT, all of the current region and of the same size
# (WIDTH pixels wide, default 600; the height follows the region):
#
#   map.png         the map: rasters PREFIX.red, PREFIX.green, PREFIX.blue
#   classes.png     the classified map PREFIX_classes (r.histo.classify's
#                   colours by class name) and its legend
#   plots.png       the map and the building plots <plots> (red outlines)
#   aligned.png     the map, the plots and the aligned footprints <aligned>
#   footprints.png  the map and the footprints <footprints>: aligned (blue)
#                   and generated (orange) from their column `source`
#
# A picture whose map was not made (a stage skipped) is not written. The
# pictures of a real map are derived from it: they stay in OUT, never in the
# repository.

stage_pictures() (  # a subshell: the GRASS_RENDER_* settings stay inside
    local out=$1 prefix=$2 width=${3:-600} height
    local rgb="red=$prefix.red green=$prefix.green blue=$prefix.blue"
    eval "$(g.region -g | grep -E '^(rows|cols)=')"
    height=$(( (width * rows + cols / 2) / cols ))
    export GRASS_RENDER_IMMEDIATE=cairo GRASS_RENDER_WIDTH=$width GRASS_RENDER_HEIGHT=$height
    export GRASS_RENDER_TRUECOLOR=TRUE GRASS_RENDER_FILE_READ=FALSE GRASS_RENDER_BACKGROUNDCOLOR=FFFFFF
    # the legend entries of d.vect, drawn by d.legend.vect (one file per picture)
    export GRASS_LEGEND_FILE=$out/.legend.txt

    # the map alone: one picture and the background of the vector ones
    background() {
        export GRASS_RENDER_FILE=$out/$1 GRASS_RENDER_FILE_READ=FALSE
        rm -f "$GRASS_LEGEND_FILE"
        d.rgb $rgb --quiet
        export GRASS_RENDER_FILE_READ=TRUE
    }
    legend() {
        d.legend.vect -b at=2,98 fontsize=13 symbol_size=16 border_width=1 --quiet
        rm -f "$GRASS_LEGEND_FILE"
    }
    exists() { [ -n "$(g.list type="$1" pattern="$2")" ]; }

    background map.png

    if exists raster "${prefix}_classes"; then
        export GRASS_RENDER_FILE=$out/classes.png GRASS_RENDER_FILE_READ=FALSE
        d.rast map="${prefix}_classes" --quiet
        GRASS_RENDER_FILE_READ=TRUE d.legend -c -n -b raster="${prefix}_classes" \
            at=78,96,3,6 font=sans fontsize=13 --quiet
    fi
    if exists vector plots; then
        background plots.png
        d.vect map=plots type=area color=red fill_color=none width=2 legend_label="plots" --quiet
        legend
    fi
    if exists vector plots && exists vector aligned; then
        background aligned.png
        d.vect map=plots type=area color=red fill_color=none width=2 legend_label="plots" --quiet
        d.vect map=aligned type=area color=0:0:90 fill_color=60:110:230 width=1 \
            legend_label="aligned footprints" --quiet
        legend
    fi
    if exists vector footprints; then
        background footprints.png
        d.vect map=footprints type=area where="source = 'aligned'" color=0:0:90 \
            fill_color=60:110:230 width=1 legend_label="aligned" --quiet
        d.vect map=footprints type=area where="source <> 'aligned' OR source IS NULL" \
            color=110:50:0 fill_color=250:160:50 width=1 legend_label="generated" --quiet
        if exists vector plots; then
            d.vect map=plots type=area color=red fill_color=none width=2 legend_label="plots" --quiet
        fi
        legend
    fi
)
