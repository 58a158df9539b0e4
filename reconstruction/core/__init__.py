"""What every part of the suite shares, and nothing that depends on a stage.

- ``errors``: :class:`InputError`, the one exception for bad input (a module
  turns it into one ``ERROR:`` line);
- ``messages``: what a stage tells its user (:class:`Message`), as data;
- ``options``: option texts into values (ranges, numbers, lists, ``nprocs``),
  each error naming its option;
- ``names``: GRASS's rules for map names, SQL keywords no column may be;
- ``crs``: EPSG codes, their CityJSON URLs, compound reference systems;
- ``safefile``: output files written whole or not at all;
- ``jsontext``: JSON files a user gave, parsed or refused with one error;
- ``work_limits``: how much work an option asks for, checked before any work;
- ``contract``: the columns and values that pass from one module to the next.
"""

from . import contract, crs, errors, jsontext, messages, names, options, safefile, work_limits
from .errors import InputError
from .messages import Message

__all__ = ["InputError", "Message", "contract", "crs", "errors", "jsontext", "messages", "names", "options",
           "safefile", "work_limits"]
