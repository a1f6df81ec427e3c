"""Reading problem files (YAML or JSON) and checking fields with errors that name the
file, the field and the reason (STYLE.md, point 2); writing output files atomically
(:func:`write_output`, :func:`atomic_output`). Both halves of plansynth use this.

Every file plansynth reads (problem files, result JSON files, ``.sl`` and program
files) goes through :func:`read_text`, and every YAML/JSON document through
:func:`load_document`, so one set of limits holds for all of them (README, "Formats and
extensions"): a regular file of at most :data:`MAX_FILE_BYTES`, UTF-8 text, nesting of
at most :data:`MAX_NESTING` levels and at most :data:`MAX_NODES` values, counting every
use of a YAML alias as a copy of what it names (a "billion laughs" document is refused
before anything expands it). A hostile file is an :class:`InvalidProblem`, never a
traceback, a hang or a memory blow-up.

One module per part: ``documents`` (reading files and parsing documents within the
limits), ``strict_yaml`` (the YAML loader that enforces them), ``fields`` (checking a
document's fields: :class:`Fields`, the ``as_*`` readers) and ``output`` (checking and
writing output files atomically).
"""

from plansynth.io.documents import MAX_FILE_BYTES, decode_utf8, load_document, parse_document, read_text
from plansynth.io.fields import (
    MAX_NAME_LENGTH,
    Fields,
    as_float,
    as_float_vector,
    as_int,
    as_int_vector,
    as_name,
    show,
    type_name,
)
from plansynth.io.output import atomic_output, check_output_folder, check_output_path, write_output
from plansynth.io.strict_yaml import MAX_NESTING, MAX_NODES

__all__ = [
    "MAX_FILE_BYTES",
    "MAX_NESTING",
    "MAX_NODES",
    "MAX_NAME_LENGTH",
    "read_text",
    "decode_utf8",
    "load_document",
    "parse_document",
    "Fields",
    "show",
    "type_name",
    "as_int",
    "as_int_vector",
    "as_float",
    "as_float_vector",
    "as_name",
    "check_output_path",
    "check_output_folder",
    "atomic_output",
    "write_output",
]
