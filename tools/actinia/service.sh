#!/bin/bash
# Start or stop Redis and actinia on 127.0.0.1 for the histo suite (issue 30;
# safe by construction, issue 49).
#
#   bash tools/actinia/service.sh start DIR [PORT] [REDIS_PORT]
#   bash tools/actinia/service.sh server DIR PORT      (one more REST server)
#   bash tools/actinia/service.sh worker DIR NAME      (one queue worker)
#   bash tools/actinia/service.sh stop DIR
#
# Run it as an unprivileged user that owns DIR (README, "A map series on
# actinia"): everything it starts runs as that user, and DIR is made 0700.
#
# start: makes, once per DIR (a per-install secret, kept across restarts),
# random secrets in files of mode 0600: DIR/redis.password (Redis's
# requirepass), DIR/secret_key (actinia's token key) and DIR/credentials
# (JSON: the actinia user histo and its password, what
# `tools/histo_series.py --credentials DIR/credentials` reads). It writes
# DIR/redis.conf and DIR/actinia.cfg (0600: they hold the Redis password;
# GRASS database, resources and temporary files all under DIR; the suite
# staged in DIST as the GRASS addon path; queue_type=local: the REST server
# runs the jobs itself), makes the location DIR/grassdb/histo
# (EPSG:$EPSG, default 28992), starts redis-server (requirepass, not
# saving anything; it refuses to go on if Redis answers without the
# password) and actinia (gunicorn) each in its own process group, makes the
# actinia user histo with the role `user` (not admin), allowed only the
# location histo and the chain's modules, and waits until actinia answers.
# Prints the URL.
#
# actinia is served behind the gate tools/actinia/gate.py
# (reconstruction.series.gate): only the routes a series needs, process
# chains of the chain's modules only, every file path in them inside the
# work folder WORK (default DIR/work: put the series' files there); the
# jobs run in the empty folder DIR/workspace/jobs.
#
# With QUEUES=N (N > 0) start writes queue_type=redis with N queues
# (job_queue_0 ... job_queue_N-1, filled in turn by the REST servers) and
# starts no worker: `worker` starts one (rq's worker from actinia's venv,
# listening to every queue, so whichever worker is free takes the next job;
# actinia 4.14.1's own actinia-worker imports rq's Connection, which the
# pinned rq 3.0.0 no longer has; the Redis password reaches it in
# RQ_REDIS_URL, not on its command line), `server` another REST server on
# PORT; both read DIR/actinia.cfg, as the processes of other machines
# sharing DIR and Redis would (README, "Several machines").
#
# stop: ends every process group started in DIR (TERM, then KILL after 2 s
# for actinia's servers and workers, 10 s for Redis) and removes their pid
# files.
#
# ACTINIA_VENV (default ~/.local/share/histo/actinia-venv, made by `make
# actinia`), HISTO_VENV (the suite's venv: the modules run with its
# python3), DIST (the staged suite, default ./dist) and WORK can be set.
set -euo pipefail
umask 077                  # every file the service writes: its user's only
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

#: the modules of a sheet's chain (demo/series/sheet_chain.json; r.resample
#: stands for r.patch on a sheet without neighbours) besides the suite's own
chain_modules="db.connect r.in.gdal r.patch r.resample g.region v.in.ogr v.overlay v.to.db v.extract"
location=histo

start_server() {  # start_server PORT PIDFILE: a REST server of DIR/actinia.cfg on PORT
  local port=$1
  mkdir -p "$dir/workspace/jobs"
  PATH="$histo_venv/bin:$PATH" HISTO_WORK=$(cfg_value histo_work) \
    HISTO_MODULES=$(cfg_value histo_modules) \
    HISTO_LOCATION=$location setsid "$actinia_venv/bin/gunicorn" -b "127.0.0.1:$port" -w 1 \
    --timeout 86400 --chdir "$dir/workspace/jobs" --pythonpath "$root/tools/actinia" \
    --control-socket "$dir/gunicorn_$port.ctl" \
    gate:app > "$dir/actinia_$port.log" 2>&1 < /dev/null &
  echo $! > "$2"
  for _ in $(seq 300); do
    curl -sf "http://127.0.0.1:$port/api/v3/version" > /dev/null 2>&1 && break
    sleep 0.2
  done
  curl -sf "http://127.0.0.1:$port/api/v3/version" > /dev/null \
    || { tail -30 "$dir/actinia_$port.log"; echo "actinia did not start"; exit 1; }
  echo "http://127.0.0.1:$port"
}

secret() {  # secret FILE: make FILE (0600) hold a random secret, once
  [ -s "$1" ] || head -c 32 /dev/urandom | base64 | tr -d '/+=\n' > "$1"
  chmod 600 "$1"
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
    mkdir -p "$dir/workspace/jobs"
    (cd "$dir/workspace/jobs" && PATH="$histo_venv/bin:$PATH" \
      RQ_REDIS_URL="redis://:$(cat "$dir/redis.password")@$(cfg_value redis_queue_server_url):$(cfg_value redis_queue_server_port)" \
      exec setsid "$actinia_venv/bin/rq" worker -n "histo_$name" \
      "${queues[@]}" > "$dir/worker_$name.log" 2>&1 < /dev/null) &
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

[ "$(id -u)" != 0 ] || echo "warning: the service runs as root: run it as an unprivileged user (README, \"A map series on actinia\")" >&2
chmod 700 "$dir"
work=${WORK:-$dir/work}
mkdir -p "$work"
work=$(cd "$work" && pwd -P)
suite_modules=$(cd "$dist/scripts" && ls | grep '^[rv]\.histo\.' | paste -sd' ')
mkdir -p "$dir/grassdb" "$dir/userdata" "$dir/workspace/temp_db" "$dir/workspace/tmp" \
  "$dir/workspace/download_cache" "$dir/workspace/jobs" "$dir/resources"
secret "$dir/redis.password"
secret "$dir/secret_key"
if [ ! -s "$dir/credentials" ]; then
  printf '{"user": "histo", "password": "%s"}\n' "$(head -c 32 /dev/urandom | base64 | tr -d '/+=\n')" \
    > "$dir/credentials"
fi
chmod 600 "$dir/credentials"
redis_password=$(cat "$dir/redis.password")
cat > "$dir/actinia.cfg" <<CFG
[GRASS]
grass_database = $dir/grassdb
grass_user_database = $dir/userdata
grass_default_location = $location
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
redis_server_pw = $redis_password
worker_logfile = $dir/workspace/tmp/worker.log

[QUEUE]
queue_type = $([ "$queues" -gt 0 ] && echo redis || echo local)
number_of_workers = $([ "$queues" -gt 0 ] && echo "$queues" || echo 3)
redis_queue_server_url = 127.0.0.1
redis_queue_server_port = $redis_port
redis_queue_server_password = $redis_password

[MISC]
tmp_workdir = $dir/workspace/tmp
download_cache = $dir/workspace/download_cache
secret_key = $(cat "$dir/secret_key")

[LOGGING]
log_level = 2
log_interface = stdout

[MANAGEMENT]
additional_allowed_modules = [$(echo $chain_modules $suite_modules | sed "s/[^ ]*/'&'/g; s/ /, /g")]

[HISTO]
histo_work = $work
histo_modules = $(echo $chain_modules $suite_modules | tr ' ' ,)
CFG
chmod 600 "$dir/actinia.cfg"
if [ ! -d "$dir/grassdb/$location/PERMANENT" ]; then
  grass -c "EPSG:$epsg" "$dir/grassdb/$location" -e > "$dir/location.log" 2>&1
fi

cat > "$dir/redis.conf" <<CONF
port $redis_port
bind 127.0.0.1
protected-mode yes
requirepass $redis_password
save ""
appendonly no
dir $dir
CONF
chmod 600 "$dir/redis.conf"
grep -Eq '^requirepass [^ ]{20,}$' "$dir/redis.conf" \
  || { echo "refusing to start Redis without a password" >&2; exit 1; }
setsid redis-server "$dir/redis.conf" > "$dir/redis.log" 2>&1 < /dev/null &
echo $! > "$dir/redis.pid"
for _ in $(seq 100); do
  REDISCLI_AUTH=$redis_password redis-cli -p "$redis_port" ping > /dev/null 2>&1 && break; sleep 0.1
done
REDISCLI_AUTH=$redis_password redis-cli -p "$redis_port" ping | grep -q PONG \
  || { cat "$dir/redis.log"; stop_group "$dir/redis.pid" 10; exit 1; }
if ! env -u REDISCLI_AUTH redis-cli -p "$redis_port" ping 2>&1 | grep -q NOAUTH; then
  echo "Redis on port $redis_port answers without the password: refusing to go on" >&2
  stop_group "$dir/redis.pid" 10
  exit 1
fi

# the user histo: role user, the location histo, the chain's modules only;
# its password from DIR/credentials (never on a command line)
USER_MODULES=$(cfg_value histo_modules) LOCATION=$location "$actinia_venv/bin/python3" - "$dir/credentials" \
  > "$dir/user.log" 2>&1 <<'PY' || { cat "$dir/user.log"; stop_group "$dir/redis.pid" 10; exit 1; }
import json, os, sys
from actinia_core.core.common.config import global_config
from actinia_core.core.common.user import ActiniaUser
from actinia_core.core.redis_user import redis_user_interface

global_config.read(os.environ["DEFAULT_CONFIG_PATH"])
redis_user_interface.connect(host=global_config.REDIS_SERVER_URL,
                             port=global_config.REDIS_SERVER_PORT,
                             password=global_config.REDIS_SERVER_PW)
with open(sys.argv[1]) as f:
    credentials = json.load(f)
user = ActiniaUser(user_id=credentials["user"], user_group="histo")
if user.exists():
    user.delete()
user = ActiniaUser(user_id=credentials["user"], user_group="histo")
user.set_role("user")
user.hash_password(credentials["password"])
user.set_accessible_datasets({os.environ["LOCATION"]: ["PERMANENT"]})
user.set_accessible_modules(os.environ["USER_MODULES"].split(","))
assert user.commit(), "the user was not written"
print("user", credentials["user"], "role user,", len(user.accessible_modules), "modules")
PY
start_server "$port" "$dir/actinia.pid"
