#!/bin/bash
# Start or stop Redis and actinia on 127.0.0.1 for the histo suite (issue 30).
#
#   bash tools/actinia/service.sh start DIR [PORT] [REDIS_PORT]
#   bash tools/actinia/service.sh server DIR PORT      (one more REST server)
#   bash tools/actinia/service.sh worker DIR NAME      (one queue worker)
#   bash tools/actinia/service.sh stop DIR
#
# start: writes DIR/actinia.cfg (GRASS database, resources and temporary
# files all under DIR; the suite staged in DIST as the GRASS addon path, its
# modules and the import/cut/extract modules its chain uses added to
# additional_allowed_modules; queue_type=local: the REST server runs the
# jobs itself, no separate worker processes), makes the location
# DIR/grassdb/histo (EPSG:$EPSG, default 28992), starts redis-server (not
# saving anything) and actinia (gunicorn) each in its own process group,
# makes the user histo (password histo) allowed to run those modules in that
# location, and waits until actinia answers. Prints the URL.
#
# With QUEUES=N (N > 0) start writes queue_type=redis with N queues
# (job_queue_0 ... job_queue_N-1, filled in turn by the REST servers) and
# starts no worker: `worker` starts one (rq's worker from actinia's venv,
# listening to every queue, so whichever worker is free takes the next job;
# actinia 4.14.1's own actinia-worker imports rq's Connection, which the
# pinned rq 3.0.0 no longer has), `server` another REST server on PORT; both read
# DIR/actinia.cfg, as the processes of other machines sharing DIR and Redis
# would (README, "Several machines").
#
# stop: ends every process group started in DIR (TERM, then KILL after 2 s
# for actinia's servers and workers, 10 s for Redis) and removes their pid
# files.
#
# ACTINIA_VENV (default ~/.local/share/histo/actinia-venv, made by `make
# actinia`), HISTO_VENV (the suite's venv: the modules run with its
# python3) and DIST (the staged suite, default ./dist) can be set.
set -euo pipefail
command=${1:?start or stop}
dir=${2:?folder of the service}
mkdir -p "$dir"
dir=$(cd "$dir" && pwd)
root=$(cd "$(dirname "$0")/../.." && pwd)

stop_group() {  # stop_group PIDFILE SECONDS: TERM, then KILL after SECONDS
  local pidfile=$1 pid
  [ -f "$pidfile" ] || return 0
  pid=$(cat "$pidfile")
  if kill -0 "$pid" 2> /dev/null; then
    kill -TERM -- "-$pid" 2> /dev/null || true
    for _ in $(seq $(( $2 * 10 ))); do kill -0 "$pid" 2> /dev/null || break; sleep 0.1; done
    kill -KILL -- "-$pid" 2> /dev/null || true
  fi
  rm -f "$pidfile"
}

# the modules run with the suite's python3 (#!/usr/bin/env python3)
actinia_venv=${ACTINIA_VENV:-$HOME/.local/share/histo/actinia-venv}
histo_venv=${HISTO_VENV:-$HOME/.local/share/histo/venv}
export DEFAULT_CONFIG_PATH="$dir/actinia.cfg"

start_server() {  # start_server PORT PIDFILE: a REST server of DIR/actinia.cfg on PORT
  local port=$1
  PATH="$histo_venv/bin:$PATH" setsid "$actinia_venv/bin/gunicorn" -b "127.0.0.1:$port" -w 1 \
    --timeout 86400 --chdir "$dir" --control-socket "$dir/gunicorn_$port.ctl" \
    actinia_core.main:flask_app > "$dir/actinia_$port.log" 2>&1 < /dev/null &
  echo $! > "$2"
  for _ in $(seq 300); do
    curl -sf -u histo:histo "http://127.0.0.1:$port/api/v3/version" > /dev/null 2>&1 && break
    sleep 0.2
  done
  curl -sf -u histo:histo "http://127.0.0.1:$port/api/v3/version" > /dev/null \
    || { tail -30 "$dir/actinia_$port.log"; echo "actinia did not start"; exit 1; }
  echo "http://127.0.0.1:$port"
}

cfg_value() {  # cfg_value KEY: its value in DIR/actinia.cfg
  sed -n "s/^$1 = //p" "$dir/actinia.cfg" | head -1
}

case $command in
  stop)
    # actinia's process queue (a child of the gunicorn worker) keeps gunicorn's
    # TERM handler and does not end on TERM, and the worker waits for it:
    # KILL after 2 s (no job outlives a stop; Redis saves nothing)
    for pidfile in "$dir"/actinia.pid "$dir"/server_*.pid "$dir"/worker_*.pid; do
      stop_group "$pidfile" 2
    done
    stop_group "$dir/redis.pid" 10
    echo "actinia and redis in $dir stopped"
    exit 0 ;;
  server)
    port=${3:?the port of the server}
    [ -f "$dir/actinia.cfg" ] || { echo "no $dir/actinia.cfg: start first" >&2; exit 1; }
    start_server "$port" "$dir/server_$port.pid"
    exit 0 ;;
  worker)
    name=${3:?the name of the worker}
    [ "$(cfg_value queue_type)" = redis ] || { echo "$dir/actinia.cfg has no redis queue (QUEUES=N start)" >&2; exit 1; }
    queues=()
    for k in $(seq 0 $(( $(cfg_value number_of_workers) - 1 ))); do queues+=("job_queue_$k"); done
    PATH="$histo_venv/bin:$PATH" setsid "$actinia_venv/bin/rq" worker -n "histo_$name" \
      -u "redis://$(cfg_value redis_queue_server_url):$(cfg_value redis_queue_server_port)" \
      "${queues[@]}" > "$dir/worker_$name.log" 2>&1 < /dev/null &
    echo $! > "$dir/worker_$name.pid"
    echo "worker $name on ${queues[*]}"
    exit 0 ;;
  start) ;;
  *) echo "usage: $0 start|server|worker|stop DIR ..." >&2; exit 2 ;;
esac

port=${3:-8088}
redis_port=${4:-6379}
dist=${DIST:-$root/dist}
queues=${QUEUES:-0}
epsg=${EPSG:-28992}
grass_base=$(grass --config path)
[ -x "$actinia_venv/bin/gunicorn" ] || { echo "actinia is not installed in $actinia_venv (make actinia)" >&2; exit 1; }
command -v redis-server > /dev/null || { echo "redis-server not found (Debian package redis-server)" >&2; exit 1; }
[ -x "$dist/scripts/v.histo.lod2" ] || { echo "the suite is not staged in $dist (make build)" >&2; exit 1; }

modules=$(cd "$dist/scripts" && ls | grep '^[rv]\.histo\.' | sed "s/.*/'&'/" | paste -sd,)
mkdir -p "$dir/grassdb" "$dir/userdata" "$dir/workspace/temp_db" "$dir/workspace/tmp" \
  "$dir/workspace/download_cache" "$dir/resources"
cat > "$dir/actinia.cfg" <<CFG
[GRASS]
grass_database = $dir/grassdb
grass_user_database = $dir/userdata
grass_default_location = histo
grass_tmp_database = $dir/workspace/temp_db
grass_resource_dir = $dir/resources
grass_gis_base = $grass_base
grass_gis_start_script = $(command -v grass)
grass_addon_path = $dist

[API]
plugins = []
authentication = True

[LIMITS]
max_cell_limit = 2000000000
process_time_limt = 86400
process_num_limit = 1000

[REDIS]
redis_server_url = 127.0.0.1
redis_server_port = $redis_port
worker_logfile = $dir/workspace/tmp/worker.log

[QUEUE]
queue_type = $([ "$queues" -gt 0 ] && echo redis || echo local)
number_of_workers = $([ "$queues" -gt 0 ] && echo "$queues" || echo 3)
redis_queue_server_url = 127.0.0.1
redis_queue_server_port = $redis_port

[MISC]
tmp_workdir = $dir/workspace/tmp
download_cache = $dir/workspace/download_cache
secret_key = histo-$(date +%s%N)

[LOGGING]
log_level = 2
log_interface = stdout

[MANAGEMENT]
additional_allowed_modules = ['db.connect', 'r.in.gdal', 'v.in.ogr', 'v.to.db', 'v.extract', $modules]
CFG
if [ ! -d "$dir/grassdb/histo/PERMANENT" ]; then
  grass -c "EPSG:$epsg" "$dir/grassdb/histo" -e > "$dir/location.log" 2>&1
fi

setsid redis-server --port "$redis_port" --bind 127.0.0.1 --save '' --appendonly no \
  --dir "$dir" > "$dir/redis.log" 2>&1 < /dev/null &
echo $! > "$dir/redis.pid"
for _ in $(seq 100); do
  redis-cli -p "$redis_port" ping > /dev/null 2>&1 && break; sleep 0.1
done
redis-cli -p "$redis_port" ping > /dev/null || { cat "$dir/redis.log"; exit 1; }

"$actinia_venv/bin/actinia-user" create -u histo -w histo -r admin -g histo \
  -d histo/PERMANENT > "$dir/user.log" 2>&1 || { cat "$dir/user.log"; exit 1; }
start_server "$port" "$dir/actinia.pid"
