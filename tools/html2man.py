#!/usr/bin/env python3
"""A module's man page in plain ASCII, readable by `g.manual -m` in any locale.

    python3 tools/html2man.py GRASS_HTML2MAN PAGE.html PAGE.1

GRASS's Make system builds each manual page (dist/docs/man/man1/<module>.1)
from the HTML page with GRASS_HTML2MAN ($GISBASE/utils/g.html2man.py);
tools/man.make makes it call this script instead, which runs that converter
and then rewrites its page so that man's output is ASCII only. Why: on a
fresh Debian minbase GRASS sets LANG=en_US, a locale that is not generated
there, so man cannot set its locale; it still formats for a UTF-8 terminal
(LC_CTYPE is a UTF-8 locale), and `col`, through which man sends the page
whenever its output is not a terminal, then prints every non-ASCII byte as
an escape (`\\xe2\\x80\\x99`). Two things make non-ASCII output:

- characters of the page itself: the HTML's entities (&ndash;, &times;,
  &nbsp;, ...), which g.html2man writes as Unicode, and GRASS's own
  non-breaking spaces and copyright sign. They are spelt in ASCII here
  (SPELLINGS), the no-break space as groff's unbreakable space;
- glyphs groff's utf8 device draws in Unicode whatever the input: the
  hyphen (also at a line break), the quote g.html2man writes for every
  apostrophe, the bullet of list items, the minus sign. A few requests
  after the page's .TH line (PREAMBLE) draw them in ASCII on that device.

The HTML pages are not touched: a browser shows them as written.
"""

import subprocess
import sys
import unicodedata

# What each character of the manual pages is in ASCII, as roff text: "'" and
# "." could start a control line and '"' ends a macro's argument, so none of
# them is written bare.
SPELLINGS = {
    "\u00a0": "\\ ",      # no-break space: groff's unbreakable space
    "\u00a9": "(C)",
    "\u00b0": " deg",
    "\u00b1": "+/-",
    "\u00b2": "^2",
    "\u00b7": "*",
    "\u00d7": "x",
    "\u00fc": "ue",
    "\u03b1": "alpha",
    "\u03c0": "pi",
    "\u03c6": "phi",
    "\u2013": "-",
    "\u2014": "--",
    "\u2018": "\\(aq",
    "\u2019": "\\(aq",
    "\u201c": "\\(dq",
    "\u201d": "\\(dq",
    "\u2212": "\\-",
    "\u221a": "sqrt",
    "\u2229": "&",
    "\u2264": "<=",
    "\u2265": ">=",
}

# groff glyphs that its utf8 device draws outside ASCII (hy U+2010, cq
# U+2019, bu U+2022, mi U+2212 where the system's man.local does not already
# map it), drawn as ASCII (\N: the glyph of that code) on that device only;
# the hyphen groff adds where it breaks a word is the soft hyphen character
# (shc), not \[hy].
PREAMBLE = (
    ".\\\" ASCII on a UTF-8 terminal too: see histo's tools/html2man.py\n"
    ".if '\\*[.T]'utf8' \\{\\\n"
    ".  char \\[hy] \\N'45'\n"
    ".  shc \\N'45'\n"
    ".  char \\[cq] \\N'39'\n"
    ".  char \\[bu] \\N'42'\n"
    ".  char \\[mi] \\N'45'\n"
    ".\\}\n"
)


def ascii_spelling(char):
    """`char` in ASCII roff text; ValueError for a character with no spelling."""
    if char in SPELLINGS:
        return SPELLINGS[char]
    # accented Latin letters: the letter without its accents
    plain = "".join(c for c in unicodedata.normalize("NFKD", char)
                    if not unicodedata.combining(c))
    if plain and plain.isascii() and plain.isalnum():
        return plain
    raise ValueError("no ASCII spelling for {!r} (U+{:04X} {}): add one to SPELLINGS of {}"
                     .format(char, ord(char), unicodedata.name(char, "?"), __file__))


def ascii_page(page):
    """The groff text `page` with every character ASCII and PREAMBLE after .TH."""
    text = "".join(c if c.isascii() else ascii_spelling(c) for c in page)
    head, newline, rest = text.partition("\n")
    if head.startswith(".TH "):
        return head + newline + PREAMBLE + rest
    return PREAMBLE + text


def main(converter, html, man):
    subprocess.run([sys.executable, converter, html, man], check=True)
    with open(man, encoding="utf-8") as f:
        page = f.read()
    try:
        page = ascii_page(page)
    except ValueError as err:
        sys.exit("{}: {}".format(html, err))
    with open(man, "w", encoding="ascii") as f:
        f.write(page)


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit(__doc__.split("\n\n")[1])
    main(*sys.argv[1:])
