"""Validation of names used in generated code (C99 and IEC 61131-3 identifiers)."""

from __future__ import annotations

import re

from ..errors import ConfigError

#: C99 keywords, C11 additions and names a prefix must not shadow.
C_KEYWORDS = frozenset(
    """
auto break case char const continue default do double else enum extern float for goto if
inline int long register restrict return short signed sizeof static struct switch typedef
union unsigned void volatile while _Bool _Complex _Imaginary _Alignas _Alignof _Atomic
_Generic _Noreturn _Static_assert _Thread_local bool true false NULL main
""".split()
)

#: IEC 61131-3 (3rd edition) keywords and standard type names, upper case.
ST_KEYWORDS = frozenset(
    """
ABS ACTION AND ANY ANY_BIT ANY_DATE ANY_INT ANY_NUM ANY_REAL ARRAY AT BOOL BY BYTE CASE
CONFIGURATION CONSTANT DATE DATE_AND_TIME DINT DO DT DWORD ELSE ELSIF END_ACTION END_CASE
END_CONFIGURATION END_FOR END_FUNCTION END_FUNCTION_BLOCK END_IF END_PROGRAM END_REPEAT
END_RESOURCE END_STEP END_STRUCT END_TRANSITION END_TYPE END_VAR END_WHILE EN ENO EXIT
EXP F_EDGE FALSE FOR FROM FUNCTION FUNCTION_BLOCK IF INITIAL_STEP INT INTERVAL LINT LREAL
LWORD MOD NON_RETAIN NOT OF ON OR PROGRAM R_EDGE READ_ONLY READ_WRITE REAL REPEAT RESOURCE
RETAIN RETURN SINT STEP STRING STRUCT TASK THEN TIME TIME_OF_DAY TO TOD TRANSITION TRUE
TYPE UDINT UINT ULINT UNTIL USINT VAR VAR_ACCESS VAR_CONFIG VAR_EXTERNAL VAR_GLOBAL
VAR_INPUT VAR_IN_OUT VAR_OUTPUT VAR_TEMP WHILE WITH WORD WSTRING XOR SQRT LN LOG SIN COS
TAN ASIN ACOS ATAN EXPT MOVE SEL MAX MIN LIMIT MUX METHOD INTERFACE CLASS EXTENDS
IMPLEMENTS THIS SUPER ABSTRACT FINAL OVERRIDE PUBLIC PRIVATE PROTECTED INTERNAL REF_TO
REF NULL
""".split()
)

_C_IDENT = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
_ST_IDENT = re.compile(r"[A-Za-z]([A-Za-z0-9]|_(?=[A-Za-z0-9]))*\Z")


def check_c_identifier(name: str, key: str = "prefix") -> str:
    """Return ``name`` if it is a valid C99 identifier and not a keyword, else raise.

    Names beginning with ``__`` or ``_`` + capital are reserved by the C standard.
    """
    if not isinstance(name, str) or not _C_IDENT.match(name):
        raise ConfigError(key, "a C identifier (letter or _, then letters, digits, _)", name)
    if name in C_KEYWORDS or name.startswith("__") or re.match(r"_[A-Z]", name):
        raise ConfigError(key, "a C identifier that is not a keyword or reserved name", name)
    return name


def check_st_identifier(name: str, key: str = "prefix") -> str:
    """Return ``name`` if it is a valid IEC 61131-3 identifier and not a keyword, else raise.

    IEC 61131-3 identifiers start with a letter (here; a leading underscore is
    legal but reserved by many vendors), contain no double underscore and do
    not end with one; keywords are case-insensitive.
    """
    if not isinstance(name, str) or not _ST_IDENT.match(name):
        raise ConfigError(
            key, "an IEC 61131-3 identifier (letter, then letters, digits, single underscores)", name
        )
    if name.upper() in ST_KEYWORDS:
        raise ConfigError(key, "an IEC 61131-3 identifier that is not a keyword", name)
    return name
