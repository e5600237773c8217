"""Names taken from input files, made safe for each kind of output: one function per kind.

A name in a user's file (a leg's ``name``, a FOLD ``file_title``, a design file's stem,
a route file's stem) reaches file names, TOML, XML, HTML, slicer configs and log lines.
Every such place goes through the one function of its kind here, never through a local
``replace``:

==================== ==================================================================
:func:`path_component` a file name inside an output folder: refused (``ValueError``
                       with the reason) unless it is one plain component
:func:`toml_string`    a TOML basic string, quotes included
:func:`toml_key`       a TOML key: bare when it can be, quoted otherwise
:func:`one_line`       a TOML comment, an error or log line: nothing can start a new line
:func:`xml_text`       XML content and attribute values (either quote)
:func:`html_text`      HTML content and attribute values (either quote)
:func:`slicer_value`   a value of PrusaSlicer's ``; key = value`` config lines
:func:`plot_text`      a title, label or legend entry of a matplotlib plot
==================== ==================================================================

Characters no output of the kind can hold become U+FFFD (XML, HTML) or an escape
(``\\n``, ``\\u202e``); the escapers never fail.

>>> toml_string('front "left"\\n[evil]')
'"front \\\\"left\\\\"\\\\n[evil]"'
>>> xml_text("' onload='alert(1)")
'&apos; onload=&apos;alert(1)'
>>> path_component("../../x")
Traceback (most recent call last):
...
ValueError: '../../x' cannot be a file name: it holds '/'
"""

from __future__ import annotations

import html
import re
import unicodedata

__all__ = [
    "html_text",
    "one_line",
    "path_component",
    "plot_text",
    "slicer_value",
    "toml_key",
    "toml_string",
    "visible",
    "xml_text",
]

#: Longest name accepted as a file name component, characters.
MAX_COMPONENT = 100

_RESERVED = set('/\\:*?"<>|')
_WINDOWS = {"con", "prn", "aux", "nul", *(f"{d}{k}" for d in ("com", "lpt") for k in range(10))}
# categories that cannot be seen or that start lines: controls, format (bidirectional
# overrides, zero-width), surrogates, private use, unassigned, line and paragraph separators
_INVISIBLE = {"Cc", "Cf", "Cs", "Co", "Cn", "Zl", "Zp"}


def _hidden(c: str) -> bool:
    return unicodedata.category(c) in _INVISIBLE


def visible(text: str) -> bool:
    """Whether every character of ``text`` can be seen: no control (C0 or C1, such as
    U+009B), format (bidirectional overrides such as U+202E, zero-width), private, unassigned
    or line-separating character.

    >>> visible("front left"), visible("front\u202eleft"), visible("a\x9bb")
    (True, False, False)
    """
    return not any(_hidden(c) for c in text)


def path_component(name: str) -> str:
    """``name`` unchanged if it can be one file name in an output folder, else ``ValueError``.

    Refused: empty or over :data:`MAX_COMPONENT` characters, ``.`` and ``..``, a leading
    dot (hidden files, the ``.oc-`` staging names), leading or trailing spaces, a
    trailing dot, ``/ \\ : * ? " < > |``, control, format (bidirectional) and other
    invisible characters, and the names Windows reserves (``CON``, ``NUL``, ``COM1``...).
    The message gives the reason; the caller names the file and key.
    """
    shown = repr(name)[:60]
    if not isinstance(name, str) or not name:
        raise ValueError(f"{shown} cannot be a file name: it is empty")
    if len(name) > MAX_COMPONENT or len(name.encode("utf-8", "replace")) > 2 * MAX_COMPONENT:
        raise ValueError(
            f"{shown} cannot be a file name: too long (at most {MAX_COMPONENT} characters "
            f"or {2 * MAX_COMPONENT} bytes)"
        )
    bad = next((c for c in name if c in _RESERVED or _hidden(c)), None)
    if bad is not None:
        raise ValueError(f"{shown} cannot be a file name: it holds {bad!r}")
    if name.startswith("."):
        raise ValueError(f"{shown} cannot be a file name: it starts with '.'")
    if name != name.strip() or name.endswith("."):
        raise ValueError(f"{shown} cannot be a file name: it starts or ends with a space or '.'")
    if name.split(".")[0].strip().lower() in _WINDOWS:
        raise ValueError(f"{shown} cannot be a file name: Windows reserves it")
    return name


_TOML_SHORT = {"\\": "\\\\", '"': '\\"', "\b": "\\b", "\t": "\\t", "\n": "\\n", "\f": "\\f"}
_TOML_SHORT["\r"] = "\\r"


def _toml_char(c: str) -> str:
    if c in _TOML_SHORT:
        return _TOML_SHORT[c]
    code = ord(c)
    if 0xD800 <= code < 0xE000:  # a lone surrogate: no TOML (or UTF-8) can hold it
        return "\ufffd"
    if code < 0x20 or code == 0x7F or _hidden(c):
        return f"\\u{code:04x}" if code <= 0xFFFF else f"\\U{code:08x}"
    return c


def toml_string(text: object) -> str:
    """``text`` as a TOML basic string (with its quotes) that reads back as ``text``.

    Quotes and backslashes are escaped, control and invisible characters written as
    ``\\uXXXX``, so no text can end the string, the line or the table; a lone
    surrogate (which no file can hold) becomes U+FFFD.
    """
    return '"' + "".join(_toml_char(c) for c in str(text)) + '"'


_BARE_KEY = re.compile(r"[A-Za-z0-9_-]+")


def toml_key(text: object) -> str:
    """``text`` as a TOML key: bare (``front_left``) when it can be, else a quoted string."""
    text = str(text)
    return text if _BARE_KEY.fullmatch(text) else toml_string(text)


def one_line(text: object) -> str:
    """``text`` on one line: every character that is not printable becomes its escape.

    For TOML comments, error messages and log lines: a newline in a name becomes
    ``\\n`` and cannot forge a further line (or a TOML table); bidirectional
    controls become ``\\u202e`` and cannot reorder what is shown.
    """
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in str(text))


_NOT_XML = re.compile("[^\t\n\r\x20-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]")
_XML = {"&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;", "'": "&apos;"}
_XML_SPECIAL = re.compile("[&<>\"']")


def xml_text(text: object) -> str:
    """``text`` safe as XML 1.0 content or as an attribute value in either quote.

    ``& < > " '`` become the five predefined entities (never character references,
    which lib3mf's strict reader refuses); tab, line feed and carriage return stay (a
    parser reads them as spaces in an attribute); characters XML 1.0 cannot hold at
    all (NUL, other controls, lone surrogates) become U+FFFD.
    """
    clean = _NOT_XML.sub("\ufffd", str(text))
    return _XML_SPECIAL.sub(lambda m: _XML[m.group()], clean)


_NOT_HTML = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\x7f\ud800-\udfff]")


def html_text(text: object) -> str:
    """``text`` safe as HTML content or a quoted attribute value (either quote).

    ``& < > " '`` are escaped; control characters and lone surrogates become U+FFFD.
    """
    return html.escape(_NOT_HTML.sub("\ufffd", str(text)), quote=True)


def slicer_value(text: object) -> str:
    """``text`` as the value of a ``; key = value`` line of PrusaSlicer's config.

    The value runs to the end of its line: backslashes, line breaks and tabs are
    written C-style (``\\\\``, ``\\n``, ``\\r``, ``\\t``), as PrusaSlicer writes them,
    and any other character that is not printable as its escape.
    """
    text = str(text).replace("\\", "\\\\")
    text = text.replace("\n", "\\n").replace("\r", "\\r").replace("\t", "\\t")
    return one_line(text)


def plot_text(text: object) -> str:
    """``text`` shown as itself in a matplotlib plot (title, label, legend entry).

    One line (:func:`one_line`); ``$`` is escaped, so a name such as ``$\\frac$`` is
    not parsed as mathtext (which fails on it); a leading ``_``, which would hide a
    legend entry, is kept visible.
    """
    shown = one_line(text).replace("$", r"\$")
    return "\u200b" + shown if shown.startswith("_") else shown
