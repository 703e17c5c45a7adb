"""Node and fault labels in catalog files: the allowed types, their encoding and decoding.

The columns :data:`LABEL_COLUMNS` hold graph labels: ``hypocenter`` and ``fault`` in the
events table, ``node`` in per-block tables.  A label is a ``str``, an ``int`` (NumPy
integers included, ``bool`` not) or a tuple of these (tuples may nest); anything else is
refused when the file is written (:func:`check_labels`), never stored as its ``repr``.

A column of integers, or of strings, is an ordinary Parquet column.  Any other column
(integers mixed with strings, tuples) is stored as text: each label as its canonical JSON
(compact, tuples as arrays), which decodes to the same value (arrays back to tuples, at
every depth).  The catalog's metadata names the encoded columns under the key ``labels``:

>>> encode_column(np.array([("B", 497), "A", 3], dtype=object), "hypocenter")
(array(['["B",497]', '"A"', '3'], dtype=object), 'json')
>>> decode_column(['["B",497]', '"A"', '3'], "json").tolist()
[('B', 497), 'A', 3]

so that ``metadata["labels"] == {"hypocenter": "json"}``; the key is absent when no column
is encoded.  Files written by faultnet 0.2 carry ``metadata["hypocenter_labels"] == "repr"``
instead (each label as its ``repr``); they are read with :func:`ast.literal_eval`.
"""

from __future__ import annotations

import ast
import json
import re

import numpy as np
import pandas as pd
import pyarrow as pa

from faultnet.exceptions import CatalogError, InvalidParameterError

__all__ = [
    "LABELS_KEY",
    "LABEL_COLUMNS",
    "LABEL_TAGS",
    "LEGACY_KEY",
    "check_labels",
    "conform_table",
    "decode_column",
    "decode_frame",
    "encode_column",
    "encode_frame",
    "label_tags",
    "merge_targets",
    "merged_schema",
    "with_label_tags",
]

#: the columns that hold node or fault labels
LABEL_COLUMNS = ("hypocenter", "node", "fault")
#: the metadata key naming the encoded label columns: ``{column: tag}``
LABELS_KEY = "labels"
#: the tags of :data:`LABELS_KEY`: ``"json"``, a label's canonical JSON
LABEL_TAGS = ("json",)
#: the key of files written by faultnet 0.2: ``"repr"`` (hypocentres as their ``repr``)
LEGACY_KEY = "hypocenter_labels"

_ALLOWED = "str, int (NumPy integers included, bool not) or a tuple of these (nested allowed)"
_NUMPY_INT = re.compile(r"\b(?:np|numpy)\.u?int(?:8|16|32|64)?\((-?\d+)\)")


def _offence(label):
    """The part of ``label`` that is not allowed, or None where the label is allowed."""
    if isinstance(label, (str, int, np.integer)) and not isinstance(label, (bool, np.bool_)):
        return None
    if type(label) is tuple:
        for part in label:
            bad = _offence(part)
            if bad is not None:
                return bad
        return None
    return (label,)


def _objects(labels):
    """``labels`` as a NumPy array: integer arrays as they are, all else of objects."""
    if isinstance(labels, (pd.Series, pd.Index)):
        labels = labels.to_numpy()
    if isinstance(labels, np.ndarray):
        return labels if labels.dtype.kind in "iuO" else labels.astype(object)
    return pd.Series(list(labels), dtype=object).to_numpy()  # tuples stay elements


def _strings(labels):
    """True for a pandas column of strings without a missing value (nothing more to check)."""
    return (
        isinstance(labels, pd.Series)
        and isinstance(labels.dtype, pd.StringDtype)
        and not labels.isna().any()
    )


def _unique(values):
    """The distinct objects of ``values`` (by identity: equal labels of other types stay)."""
    return dict(zip(map(id, values), values, strict=True)).values()


def check_labels(labels, what="labels"):
    """Refuse labels that a catalog file cannot give back with their type.

    Parameters
    ----------
    labels : iterable
        Node or fault labels: a graph's nodes, a column, an array.
    what : str
        What they are, for the message (``"column 'hypocenter'"``, ``"graph nodes"``).

    Raises
    ------
    InvalidParameterError
        Naming ``what``, the first label that is not a str, an int or a tuple of these,
        and its type.

    >>> check_labels([1, "a", ("B", (2, "c"))], "graph nodes")
    >>> check_labels([("B", 1.5)], "graph nodes")
    Traceback (most recent call last):
    ...
    faultnet.exceptions.InvalidParameterError: graph nodes: label ('B', 1.5) holds 1.5 of type \
float; a label must be a str, int (NumPy integers included, bool not) or a tuple of these \
(nested allowed)
    """
    if _strings(labels):
        return
    values = _objects(labels)
    if values.dtype.kind in "iu":
        return
    for label in _unique(values.ravel()):
        bad = _offence(label)
        if bad is not None:
            holds = "" if bad[0] is label else f" holds {bad[0]!r}"
            raise InvalidParameterError(
                f"{what}: label {label!r}{holds} of type {type(bad[0]).__name__}; "
                f"a label must be a {_ALLOWED}"
            )


def _plain(label):
    if isinstance(label, tuple):
        return [_plain(part) for part in label]
    return int(label) if isinstance(label, np.integer) else label


def _tupled(value):
    return tuple(_tupled(part) for part in value) if isinstance(value, list) else value


def _mapped(values, func):
    """``func`` of each value, evaluated once per distinct value, as an object array."""
    codes, uniques = pd.factorize(np.asarray(values, dtype=object), use_na_sentinel=True)
    out = np.empty(len(uniques) + 1, dtype=object)  # code -1 (a missing value) reads None
    for i, value in enumerate(uniques):
        out[i] = func(value)
    return out[codes]


def _json(labels):
    """The canonical JSON of each (allowed) label, as an object array of strings."""
    return _mapped(
        labels, lambda v: json.dumps(_plain(v), ensure_ascii=False, separators=(",", ":"))
    )


def encode_column(values, name):
    """``(values, tag)``: the column as Parquet stores it, and its tag (None: not encoded).

    Integers that fit int64, and strings, stay as they are; other allowed labels become
    their canonical JSON (``tag == "json"``).  Refuses other labels (:func:`check_labels`).
    """
    if _strings(values):
        return values, None
    objs = _objects(values)
    if objs.dtype.kind in "iu":
        return values, None
    check_labels(objs, f"column {name!r}")
    kinds = set(map(type, _unique(objs)))
    if objs.size and all(issubclass(k, str) for k in kinds):
        return values, None
    if objs.size and not any(issubclass(k, (str, tuple)) for k in kinds):  # integers only
        if -(2**63) <= min(objs) and max(objs) < 2**63:
            return values, None
    return _json(objs), "json"


def _literal(text):
    """A 0.2 ``repr`` label back to its value; the text itself where it is not a literal."""
    for source in (text, _NUMPY_INT.sub(r"\1", text)):
        try:
            return ast.literal_eval(source)
        except (ValueError, TypeError, SyntaxError, MemoryError, RecursionError):
            pass
    return text


def _from_json(text):
    try:
        return _tupled(json.loads(text))
    except (TypeError, ValueError):
        raise CatalogError(f"label {text!r} is not the JSON of a label") from None


def decode_column(values, tag):
    """The labels of a column stored with ``tag`` (``"json"`` or 0.2's ``"repr"``)."""
    if tag == "json":
        return _mapped(values, _from_json)
    if tag == "repr":
        return _mapped(values, lambda v: _literal(v) if isinstance(v, str) else v)
    raise CatalogError(f"unknown label encoding {tag!r} (known: {', '.join(LABEL_TAGS)})")


def encode_frame(frame):
    """``(frame, tags)``: the frame with its label columns as stored, and their tags."""
    tags, encoded = {}, {}
    for name in LABEL_COLUMNS:
        if name in frame.columns:
            values, tag = encode_column(frame[name], name)
            if tag is not None:
                tags[name] = tag
                encoded[name] = pd.Series(values, index=frame.index, dtype=object)
    return (frame.assign(**encoded) if encoded else frame), tags


def decode_frame(frame, tags, path=None):
    """The frame with the label columns named in ``tags`` decoded (in place; returned)."""
    for name, tag in tags.items():
        if name in frame.columns:
            try:
                values = decode_column(frame[name].to_numpy(dtype=object), tag)
            except CatalogError as exc:
                raise CatalogError(f"catalog {path}, column {name!r}: {exc}") from None
            frame[name] = pd.Series(values, index=frame.index, dtype=object)
    return frame


def label_tags(md) -> dict:
    """``{column: tag}`` of the encoded label columns named by a catalog's metadata."""
    tags = {"hypocenter": "repr"} if md.get(LEGACY_KEY) == "repr" else {}
    tags.update(md.get(LABELS_KEY) or {})
    return tags


def with_label_tags(md, tags) -> dict:
    """A copy of metadata ``md`` whose label tags are ``tags`` (and no 0.2 key)."""
    md = {k: v for k, v in md.items() if k not in (LABELS_KEY, LEGACY_KEY)}
    if tags:
        md[LABELS_KEY] = dict(sorted(tags.items()))
    return md


# --------------------------------------------------------------------------- merging parts


def _kind(typ):
    if pa.types.is_integer(typ):
        return "int"
    return "str" if pa.types.is_string(typ) or pa.types.is_large_string(typ) else "other"


def merge_targets(schemas, part_tags) -> dict:
    """``{column: (type, tag)}``: how each label column of the merged file is stored.

    A column stored alike in every part stays so (strings of two widths take the first
    part's); otherwise, integers in one part and strings in another, say, or a 0.2 part,
    every part's column becomes JSON text.
    """
    targets = {}
    for name in LABEL_COLUMNS:
        if not all(name in schema.names for schema in schemas):
            continue  # the parts' columns differ: the merge refuses them
        types = [schema.field(name).type for schema in schemas]
        tags = {part.get(name) for part in part_tags}
        if tags == {None} and (len(set(types)) == 1 or {_kind(t) for t in types} == {"str"}):
            targets[name] = (types[0], None)
        elif tags == {"json"} and len(set(types)) == 1:
            targets[name] = (types[0], "json")
        else:
            targets[name] = (pa.string(), "json")
    return targets


def merged_schema(schema, targets):
    """``schema`` with the label columns of ``targets`` retyped (pandas metadata included)."""
    md = dict(schema.metadata or {})
    for name, (typ, _) in targets.items():
        i = schema.get_field_index(name)
        if schema.field(i).type != typ:
            schema = schema.set(i, pa.field(name, typ))
            if b"pandas" in md:
                pandas_md = json.loads(md[b"pandas"])
                for col in pandas_md.get("columns", []):
                    if col.get("field_name") == name:
                        col.update(pandas_type="unicode", numpy_type="object", metadata=None)
                md[b"pandas"] = json.dumps(pandas_md).encode()
    return schema.with_metadata(md)


def conform_table(table, tags, targets):
    """A part's ``table`` (label tags ``tags``) with its label columns stored as ``targets``."""
    for name, (typ, tag) in targets.items():
        if name not in table.column_names:
            continue
        i = table.column_names.index(name)
        column, had = table.column(i), tags.get(name)
        if had == tag and column.type == typ:
            continue
        if had != tag:  # to JSON (the target is plain only where every part is)
            values = np.empty(len(column), dtype=object)
            values[:] = column.to_pylist()
            if had is not None:
                values = decode_column(values, had)
            check_labels(values, f"column {name!r}")
            column = pa.array(_json(values), type=pa.string())
        table = table.set_column(i, pa.field(name, typ), column.cast(typ))
    return table
