"""Names the suite writes: map names and attribute column names.

Pure rules, no GRASS: an output map name must be one GRASS accepts (and a
vector map's name is also its attribute table's), and no column or vector
map may be named by an SQL keyword, which core GRASS tools (g.copy,
v.extract where=, v.db.renamecolumn, v.patch -e) do not quote
(issue 12, item 3). The checks return the problem as text, or None.
"""

import re

#: SQL keywords that break unquoted SQL: every keyword of SQLite (GRASS's
#: default database driver, sqlite.org/lang_keywords.html) and the reserved
#: words of PostgreSQL (the other driver in common use); lower case.
SQL_KEYWORDS = frozenset("""
abort action add after all alter always analyze and as asc attach autoincrement before
begin between by cascade case cast check collate column commit conflict constraint create
cross current current_date current_time current_timestamp database default deferrable
deferred delete desc detach distinct do drop each else end escape except exclude exclusive
exists explain fail filter first following for foreign from full generated glob group groups
having if ignore immediate in index indexed initially inner insert instead intersect into is
isnull join key last left like limit match materialized natural no not nothing notnull null
nulls of offset on or order others outer over partition plan pragma preceding primary query
raise range recursive references regexp reindex release rename replace restrict returning
right rollback row rows savepoint select set table temp temporary then ties to transaction
trigger unbounded union unique update using vacuum values view virtual when where window
with without
analyse any array asymmetric authorization binary both collation concurrently
current_catalog current_role current_schema current_user false fetch freeze grant ilike
lateral leading localtime localtimestamp only overlaps placing session_user similar some
symmetric tablesample trailing true user variadic verbose
""".split())

#: longest map name GRASS takes (GNAME_MAX - 1)
NAME_MAX = 255

_VECTOR_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")
_COLUMN_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")


def is_sql_keyword(name):
    """True when ``name`` is an SQL keyword (any case)."""
    return str(name).lower() in SQL_KEYWORDS


def raster_name_problem(name):
    """Why ``name`` cannot name a new raster map (GRASS's G_legal_filename), or None."""
    if not name or name.startswith("."):
        return "a map name cannot be empty or start with '.'"
    bad = sorted({c for c in name if c in "/\"'@,=*~" or c <= " " or c >= "\177"})
    if bad:
        return "a map name cannot hold {}".format(" ".join(repr(c) for c in bad))
    if len(name) > NAME_MAX:
        return "a map name has at most {} characters".format(NAME_MAX)
    return None


def vector_name_problem(name):
    """Why ``name`` cannot name a new vector map, or None.

    GRASS's Vect_legal_filename (a letter first, then letters, digits and
    ``_``: the name is also the attribute table's) and no SQL keyword, since
    the table named after the map must be usable unquoted.
    """
    problem = raster_name_problem(name)
    if problem:
        return problem
    if not _VECTOR_NAME.match(name):
        return ("a vector map name starts with a letter and holds only letters, digits "
                "and '_' (it also names the attribute table)")
    if is_sql_keyword(name):
        return "<{}> is an SQL keyword (it would name the attribute table)".format(name)
    return None


def column_name_problem(name):
    """Why ``name`` should not name an attribute column the suite writes, or None."""
    if not _COLUMN_NAME.match(str(name)):
        return "column <{}> is not a plain SQL name".format(name)
    if is_sql_keyword(name):
        return "column <{}> is an SQL keyword".format(name)
    return None
