# Helpers shared by the chain scripts (demo/chain.sh, demo/delft_1961.sh);
# sourced, not run. They need a GRASS session.

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
