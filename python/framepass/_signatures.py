"""The signatures of the extension's functions, read from the first line of their docstrings
(pybind11 writes `name(a: int, *, b: str = 'x') -> T` there), for inspect.signature and for the
stubs (python/fix_stubs.py): one parser for both."""
import ast
import functools
import inspect
import re
from typing import Any, Callable, List, Optional, Tuple, TypeVar

F = TypeVar("F", bound=Callable[..., Any])


def parameters_text(doc: Optional[str], name: str) -> Optional[Tuple[List[str], str]]:
    """(the parameter texts, the result text) of the docstring's first line for `name`, or None
    (no docstring, or an overloaded function's)."""
    first = doc.strip().splitlines()[0] if doc and doc.strip() else ""
    m = re.match(re.escape(name) + r"\((.*)\) -> (.*)$", first)
    if not m:
        return None
    args, result = m.groups()
    # Split at the top-level commas (a type such as Dict[str, int] holds commas of its own).
    parts, depth, start = [], 0, 0
    for i, c in enumerate(args):
        if c in "[(":
            depth += 1
        elif c in "])":
            depth -= 1
        elif c == "," and depth == 0:
            parts.append(args[start:i])
            start = i + 1
    parts.append(args[start:])
    return [p.strip() for p in parts if p.strip()], result


class _Default:
    """A default that is not a Python literal, shown as pybind11 wrote it."""

    def __init__(self, text: str) -> None:
        self.text = text

    def __repr__(self) -> str:
        return self.text


def signature(doc: Optional[str], name: str) -> Optional[inspect.Signature]:
    """inspect.Signature of the docstring's first line, or None."""
    parsed = parameters_text(doc, name)
    if parsed is None:
        return None
    texts, result = parsed
    params: List[inspect.Parameter] = []
    kind = inspect.Parameter.POSITIONAL_OR_KEYWORD
    for text in texts:
        if text == "*":
            kind = inspect.Parameter.KEYWORD_ONLY
            continue
        head, _, default = text.partition("=")
        pname, _, annotation = head.partition(":")
        value: Any = inspect.Parameter.empty
        if default:
            try:
                value = ast.literal_eval(default.strip())
            except (ValueError, SyntaxError):
                value = _Default(default.strip())
        params.append(inspect.Parameter(pname.strip(), kind, default=value,
                                        annotation=annotation.strip() or inspect.Parameter.empty))
    return inspect.Signature(params, return_annotation=result.strip())


def with_signature(function: F, name: Optional[str] = None) -> F:
    """`function` (an extension function) behind a Python one that inspect.signature reads."""
    sig = signature(getattr(function, "__doc__", None), name or function.__name__)
    if sig is None:
        return function

    @functools.wraps(function)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        return function(*args, **kwargs)

    wrapper.__signature__ = sig  # type: ignore[attr-defined]
    return wrapper  # type: ignore[return-value]
