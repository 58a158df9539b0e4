"""The histo series service's WSGI application: actinia behind a gate (issue 49).

gunicorn serves ``gate:app`` (tools/actinia/service.sh): each request is
checked by :func:`reconstruction.series.gate.refusal` (the routes a series
needs; process chains of the series' modules whose file paths lie in the
work folder) before actinia's own application sees it; a refused request
gets 403 and a JSON message. The policy comes from the environment that
service.sh sets: HISTO_WORK (the work folder), HISTO_MODULES (the modules,
comma-separated), HISTO_LOCATION.
"""

import io
import json
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
if ROOT not in sys.path:
    sys.path.insert(0, ROOT)

from actinia_core.main import flask_app  # noqa: E402

from reconstruction.series import gate  # noqa: E402

POLICY = gate.Policy.of([os.environ["HISTO_WORK"]], os.environ["HISTO_MODULES"].split(","),
                        os.environ["HISTO_LOCATION"])


def app(environ, start_response):
    method = environ.get("REQUEST_METHOD", "")
    body = b""
    if method == "POST":
        body = environ["wsgi.input"].read(gate.MAX_BODY + 1)
        environ["wsgi.input"] = io.BytesIO(body)
        environ["CONTENT_LENGTH"] = str(len(body))
    why = gate.refusal(method, environ.get("PATH_INFO", ""), body, POLICY)
    if why is None:
        return flask_app(environ, start_response)
    answer = json.dumps({"status": "error", "message": "refused: " + why}).encode()
    start_response("403 Forbidden", [("Content-Type", "application/json"),
                                      ("Content-Length", str(len(answer)))])
    return [answer]
