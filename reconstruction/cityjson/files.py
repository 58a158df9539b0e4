"""A CityJSON file or CityJSONSeq read as a document: the format told by the content,
the version checked, CityJSON 1.1 upgraded to 2.0 (see
:mod:`reconstruction.cityjson.existing`, which checks and matches what is read)."""

import os

from ..core import jsontext
from ..core.errors import InputError
from . import geometry as citygeometry
from . import seq as cityjsonseq

#: the CityJSON versions read as they are, and those upgraded to 2.0 on read
VERSION = "2.0"
UPGRADED = ("1.1",)


def not_cityjson(path, why):
    return InputError("'{}' is not a CityJSON file or CityJSONSeq file ({})".format(path, why))


def check_version(path, doc):
    version = str(doc.get("version", ""))
    if version == VERSION or version in UPGRADED:
        return version
    raise InputError(
        "'{}' is CityJSON {}: only CityJSON {} and {} are read (upgrade it with "
        "cjio: cjio {} upgrade save upgraded.city.json)".format(
            path, version or "without a version", VERSION, ", ".join(UPGRADED),
            os.path.basename(path)))


def upgrade(doc):
    """CityJSON 1.1 -> 2.0 in place, by the rules of the 2.0 changelog (the
    same as cjio's ``upgrade_version_v11_v20``): the version, the metadata's
    point of contact address as an object, ``+GenericCityObject`` of the
    Generic extension back as the core ``GenericCityObject``."""
    doc["version"] = VERSION
    contact = (doc.get("metadata") or {}).get("pointOfContact")
    if isinstance(contact, dict) and isinstance(contact.get("address"), str):
        contact["address"] = {"address": contact["address"]}
    generic = (doc.get("extensions") or {}).get("Generic")
    if isinstance(generic, dict) and "generic.ext.json" in str(generic.get("url", "")):
        for obj in doc["CityObjects"].values():
            if isinstance(obj, dict) and obj.get("type") == "+GenericCityObject":
                obj["type"] = "GenericCityObject"
        del doc["extensions"]["Generic"]
    return doc


def load(path, what="existing model"):
    """The parsed file: (document, offsets, counts, sequence) as
    :func:`~reconstruction.cityjson.existing.model_of` takes them (a CityJSONSeq's
    objects keep their feature's indices); ``what`` the file is, for the error of a
    file that cannot be opened. The JSON is read by :mod:`reconstruction.core.jsontext`:
    text nested too deeply or holding a lone surrogate is an InputError too."""
    try:
        f = open(path, encoding="utf-8")
    except OSError as error:
        raise InputError("Cannot read the {} '{}': {}".format(what, path, error.strerror))
    with f, citygeometry.gc_paused(keep=True):
        try:
            # a CityJSONSeq is a complete JSON object on its first line and
            # more lines after it; a one-line CityJSON file is parsed once
            first = f.readline()
            try:
                doc = jsontext.loads(first, what, path)
            except InputError:
                doc = None              # not a whole JSON text alone: read whole below
            rest = f.readline() if isinstance(doc, dict) else ""
            while rest != "" and not rest.strip():
                rest = f.readline()
            offsets, counts, sequence = None, None, False
            if rest:
                f.seek(0)
                doc, offsets, counts = cityjsonseq.read_features(f, path)
                sequence = True
            elif doc is None:
                f.seek(0)
                doc = jsontext.loads(f.read(), what, path)
        except UnicodeDecodeError:
            raise not_cityjson(path, "not a text file") from None
    return doc, offsets, counts, sequence
