"""A griffe extension for the API reference (loaded by mkdocs.yml): what griffe does not read by itself.

- Signatures of compiled functions. griffe documents the compiled module hovi._core by inspecting
  it, and inspection finds no parameters for a pybind11 function: pybind11 writes the signature
  as the first line of the docstring instead, e.g. ``add_spring(self: hovi._core.Model, joint:
  object, stiffness: typing.SupportsFloat | typing.SupportsIndex, rest: ... = 0.0) -> None``.
  That line becomes the function's parameters and return annotation, with pybind11's types
  spelled as a reader would (``Model``, ``float``, ``int``). Functions whose docstring does not
  start with their own signature (everything written in Python) are left alone.
- Properties written as ``s = property(lambda self: ..., doc="...")`` (Integrator): shown as
  properties with their ``doc``, instead of as class attributes whose value is a lambda.
- Dataclass fields documented by a trailing comment (``q: np.ndarray  # (K+1, n) ...``, with
  continuation comment lines aligned below it): the comment becomes the field's docstring.
"""
from __future__ import annotations

import ast
import io
import re
import tokenize

import griffe

# pybind11 3's spelling of numbers and of the module's own classes -> the short form
_SHORTER = [
    ("typing.SupportsFloat | typing.SupportsIndex", "float"),
    ("typing.SupportsInt | typing.SupportsIndex", "int"),
    ("hovi._core.", ""),
]


def _short(text: str) -> str:
    for long, short in _SHORTER:
        text = text.replace(long, short)
    return text


def _parameters(arguments: ast.arguments) -> list[griffe.Parameter]:
    kind = griffe.ParameterKind
    positional = arguments.posonlyargs + arguments.args
    defaults = [None] * (len(positional) - len(arguments.defaults)) + list(arguments.defaults)
    params = []

    def add(arg, param_kind, default=None):
        annotation = _short(ast.unparse(arg.annotation)) if arg.annotation is not None else None
        params.append(griffe.Parameter(arg.arg, annotation=annotation, kind=param_kind,
                                       default=None if default is None else ast.unparse(default)))

    for i, (arg, default) in enumerate(zip(positional, defaults)):
        add(arg, kind.positional_only if i < len(arguments.posonlyargs) else kind.positional_or_keyword, default)
    if arguments.vararg:
        add(arguments.vararg, kind.var_positional)
    for arg, default in zip(arguments.kwonlyargs, arguments.kw_defaults):
        add(arg, kind.keyword_only, default)
    if arguments.kwarg:
        add(arguments.kwarg, kind.var_keyword)
    return params


def _docstring(text: str, obj: griffe.Object, agent) -> griffe.Docstring:
    return griffe.Docstring(text, parent=obj, parser=getattr(agent, "docstring_parser", None),
                            parser_options=getattr(agent, "docstring_options", None))


def _trailing_comment(lines: list[str], lineno: int, end_lineno: int) -> str | None:
    """The comment ending the statement on lines lineno..end_lineno (1-based) and the comment-only
    lines right below it that start in the same column."""
    try:
        tokens = list(tokenize.generate_tokens(io.StringIO(lines[end_lineno - 1] + "\n").readline))
    except (tokenize.TokenError, IndentationError, IndexError):
        return None
    comments = [t for t in tokens if t.type == tokenize.COMMENT]
    if not comments:
        return None
    column = comments[-1].start[1]
    parts = [comments[-1].string[1:].strip()]
    for line in lines[end_lineno:]:
        if len(line) > column and line[:column].strip() == "" and line[column] == "#":
            parts.append(line[column + 1:].strip())
        else:
            break
    return " ".join(parts)


class HoviDocs(griffe.Extension):
    def on_function_instance(self, *, node, func: griffe.Function, agent, **kwargs) -> None:
        if func.docstring is None:
            return
        first, _, rest = func.docstring.value.partition("\n")
        match = re.fullmatch(rf"{re.escape(func.name)}\((?P<params>.*)\)(?: -> (?P<returns>.+))?", first.strip())
        if not match:
            return
        try:
            tree = ast.parse(f"def f({match['params']}): pass")
        except SyntaxError:  # a default pybind11 could only print as <...>: keep the line as it is
            return
        func.parameters = griffe.Parameters(*_parameters(tree.body[0].args))
        if match["returns"]:
            func.returns = _short(match["returns"])
        func.docstring.value = rest.strip("\n")

    def on_attribute_instance(self, *, node, attr: griffe.Attribute, agent, **kwargs) -> None:
        if not isinstance(node, (ast.Assign, ast.AnnAssign)):
            return  # inspected (compiled) attributes
        value = node.value
        if (isinstance(value, ast.Call) and isinstance(value.func, ast.Name) and value.func.id == "property"):
            attr.value = None
            attr.labels.clear()
            attr.labels.add("property")
            doc = [k.value for k in value.keywords if k.arg == "doc" and isinstance(k.value, ast.Constant)]
            if doc and attr.docstring is None:
                attr.docstring = _docstring(str(doc[0].value), attr, agent)
            return
        if attr.docstring is None and isinstance(node, ast.AnnAssign) and attr.parent is not None and attr.parent.is_class:
            comment = _trailing_comment(attr.lines_collection[attr.filepath], node.lineno, node.end_lineno)
            if comment:
                attr.docstring = _docstring(comment, attr, agent)
