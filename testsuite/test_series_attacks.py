"""The two attacks of issue 49 on the map-series service, tried and failing.

The service is started as ``make test`` starts it (tools/actinia/service.sh
on 127.0.0.1, free ports, stopped whatever happens), in a folder whose
parent any local user may enter; a second local user (``nobody``, through
``runuser``) then tries:

1. code execution: a crafted pickle written into Redis as the histo user's
   permissions, which actinia unpickles on the next request: Redis answers
   NOAUTH and no file appears;
2. files: reading the service's secrets, logging in with the former fixed
   credentials histo:histo, and, with the histo user's own credentials, a
   root-only file read back through ``v.in.ogr`` + ``v.db.select`` and a
   root-owned file overwritten through a module's ``output=`` with
   ``overwrite``: every one refused, the file unchanged.

Needs root (CI runs as root) for ``runuser``.
"""

import importlib.util
import json
import os
import pickle
import shutil
import stat
import subprocess
import tempfile
import time

import pytest

import series_service

pytestmark = pytest.mark.grass
_SPEC = importlib.util.spec_from_file_location("histo_series", os.path.join(
    series_service.ROOT, "tools", "histo_series.py"))
DRIVER = importlib.util.module_from_spec(_SPEC)
_SPEC.loader.exec_module(DRIVER)
ATTACKER = "nobody"
SECRET = "TOPSECRET-{}".format(os.getpid())


@pytest.fixture(scope="module")
def place():
    """A folder any local user may enter (not pytest's 0700 one), removed afterwards."""
    missing = series_service.missing()
    if os.geteuid() != 0 or not shutil.which("runuser"):
        missing.append("root and runuser (to be a second local user)")
    if missing:
        pytest.skip("not installed: " + ", ".join(missing))
    folder = tempfile.mkdtemp(prefix="histo_attacks_")
    os.chmod(folder, 0o755)
    try:
        yield folder
    finally:
        shutil.rmtree(folder, ignore_errors=True)


@pytest.fixture(scope="module")
def service(place):
    with series_service.started(os.path.join(place, "service")) as started:
        yield started


def as_attacker(*command, stdin=None):
    proc = subprocess.run(["runuser", "-u", ATTACKER, "--"] + list(command), stdin=stdin,
                          capture_output=True, timeout=60)
    return proc.returncode, (proc.stdout + proc.stderr).decode("utf-8", "replace")


def histo_login(service):
    """The histo user's credentials (before issue 49: the fixed histo:histo)."""
    if os.path.exists(service.credentials):
        return service.user_password()
    return "histo", "histo"


def call(url, user, password, data=None):
    """(HTTP status, answer text) of one call of actinia's API (the driver's client)."""
    status, body = DRIVER.Actinia(url, user, password, "histo").answer(url, data)
    return status, body.decode("utf-8", "replace")


def run_chain(service, chain, user, password):
    """Send ``chain``; its answers (texts) up to the end of the job, if it was accepted."""
    status, answer = call(service.url + "/api/v3/locations/histo/processing_async_export",
                          user, password, chain)
    answers = [answer]
    if status == 200:
        status_url = json.loads(answer)["urls"]["status"]
        for _ in range(240):
            _, text = call(status_url, user, password)
            answers.append(text)
            if json.loads(text).get("status") in ("finished", "error", "terminated"):
                break
            time.sleep(0.5)
    return status, answers


def test_a_second_user_cannot_read_the_services_secrets(service):
    assert stat.S_IMODE(os.stat(service.folder).st_mode) == 0o700
    for name in ("credentials", "actinia.cfg", "redis.password", "secret_key", "redis.conf"):
        path = os.path.join(service.folder, name)
        assert stat.S_IMODE(os.stat(path).st_mode) == 0o600, name
        code, said = as_attacker("cat", path)
        assert code != 0 and "Permission denied" in said, (name, said)
    assert "histo" not in open(os.path.join(service.folder, "secret_key")).read()


def test_the_former_fixed_credentials_are_refused(service):
    status, answer = call(service.url + "/api/v3/locations/histo/processing_async_export",
                          "histo", "histo", {"version": "1", "list": []})
    assert status == 401, answer


def test_the_histo_user_has_the_user_role_not_admin(service):
    password = open(os.path.join(service.folder, "redis.password")).read().strip()
    role = subprocess.run(["redis-cli", "-p", str(service.redis_port), "HGET",
                           "USER-ID-HASH-PREFIX::histo", "user_role"], capture_output=True,
                          text=True, env=dict(os.environ, REDISCLI_AUTH=password)).stdout.strip()
    assert role == "user"


def test_a_root_only_file_cannot_be_read_back_through_a_process_chain(service, place):
    secret = os.path.join(place, "secret.csv")
    with open(secret, "w") as f:
        f.write("id,name\n1,{}\n".format(SECRET))
    os.chmod(secret, 0o600)
    chain = {"version": "1", "list": [
        {"id": "read", "module": "v.in.ogr", "flags": "o",
         "inputs": [{"param": "input", "value": secret}],
         "outputs": [{"param": "output", "value": "stolen"}]},
        {"id": "show", "module": "v.db.select", "inputs": [{"param": "map", "value": "stolen"}]}]}
    status, answers = run_chain(service, chain, *histo_login(service))
    assert status == 403, answers
    assert not any(SECRET in a for a in answers)
    # the modules the chain has, a path outside the work folder: refused too
    chain["list"][1] = {"id": "out", "module": "v.extract",
                        "inputs": [{"param": "input", "value": "stolen"}],
                        "outputs": [{"param": "output", "value": "x",
                                     "export": {"format": "GeoJSON", "type": "vector"}}]}
    status, answers = run_chain(service, chain, *histo_login(service))
    assert status == 403 and "outside the series' work folder" in answers[0], answers


def test_a_root_owned_file_cannot_be_overwritten_through_a_process_chain(service, place):
    target = os.path.join(place, "root_owned.png")
    with open(target, "w") as f:
        f.write("original\n")
    os.chmod(target, 0o644)
    chain = {"version": "1", "list": [
        {"id": "region", "module": "g.region",
         "inputs": [{"param": p, "value": v} for p, v in
                    (("n", "10"), ("s", "0"), ("e", "10"), ("w", "0"), ("res", "1"))]},
        {"id": "map", "module": "r.mapcalc", "inputs": [{"param": "expression",
                                                         "value": "x = 1"}]},
        {"id": "write", "module": "r.out.png", "overwrite": True,
         "inputs": [{"param": "input", "value": "x"}],
         "outputs": [{"param": "output", "value": target}]}]}
    status, answers = run_chain(service, chain, *histo_login(service))
    assert status == 403, answers
    with open(target, "rb") as f:
        assert f.read() == b"original\n"


def test_a_pickle_written_into_redis_by_a_second_user_runs_nothing(service, place):
    """Last: on a service without a Redis password this breaks the histo user."""
    marker = os.path.join(place, "pwned")

    class Payload:
        def __reduce__(self):
            return (os.system, ("id > {}".format(marker),))

    payload = os.path.join(place, "payload.pickle")
    with open(payload, "wb") as f:
        f.write(pickle.dumps({"accessible_datasets": {}, "x": Payload()}))
    os.chmod(payload, 0o644)
    with open(payload, "rb") as stdin:
        code, said = as_attacker("redis-cli", "-p", str(service.redis_port), "-x", "HSET",
                                 "USER-ID-HASH-PREFIX::histo", "permissions", stdin=stdin)
    assert "NOAUTH" in said, said
    code, said = as_attacker("redis-cli", "-p", str(service.redis_port), "CONFIG", "SET",
                             "dir", "/tmp")
    assert "NOAUTH" in said, said
    status, answer = call(service.url + "/api/v3/resources/histo/resource_id-none",
                          *histo_login(service))
    time.sleep(1)
    assert not os.path.exists(marker), open(marker).read()
