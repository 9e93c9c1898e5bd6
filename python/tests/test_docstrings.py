"""Every public function, class, method and property of spinmotor has a docstring that names each of
its inputs (the argument names of the pybind11 signature) and says what it returns, and every function
and constructor says which errors it raises (issue 18: "docstrings on every function (inputs, outputs,
errors)")."""
import inspect
import re

import pytest

import spinmotor as sm

SIGNATURE = re.compile(r"^(?:\d+\. )?(\w+)\((.*)\)(?: -> (.*))?$")
OUTPUT = re.compile(r"->|\bOutput|\breturns?\b|\bReturns?\b|\bgives\b", re.I)
ERRORS = re.compile(r"\bErrors?\b|spinmotor\.Error|\braises?\b", re.I)


def split_top(s):
    """Split a signature's parameter list at top-level commas."""
    out, depth, cur = [], 0, ""
    for ch in s:
        if ch in "([{":
            depth += 1
        elif ch in ")]}":
            depth -= 1
        if ch == "," and depth == 0:
            out.append(cur.strip())
            cur = ""
        else:
            cur += ch
    if cur.strip():
        out.append(cur.strip())
    return out


def parse(doc, name):
    """(parameter names, user text) of a pybind11 docstring: the generated signature line it starts
    with (or, for overloads, the numbered ones after "Overloaded function.") and the rest."""
    lines = doc.splitlines()
    # an overload set: "name(*args, **kwargs)", "Overloaded function.", then "1. name(...)", ...
    if len(lines) > 1 and lines[1].strip() == "Overloaded function.":
        lines = lines[1:]
    overloaded = bool(lines) and lines[0].strip() == "Overloaded function."
    params, text = [], []
    for k, line in enumerate(lines):
        m = SIGNATURE.match(line.strip())
        generated = (k == 0 and not overloaded) or (overloaded and re.match(r"^\d+\. ", line.strip()))
        if m and m.group(1) == name and generated:
            for p in split_top(m.group(2)):
                p = p.split(":")[0].split("=")[0].strip().lstrip("*")
                if p and p != "self":
                    params.append(p)
        elif not (k == 0 and overloaded):
            text.append(line)
    return params, "\n".join(text)


def public():
    for name in sorted(sm.__all__):
        yield name, getattr(sm, name)


def members(cls):
    for name, obj in vars(cls).items():
        if name.startswith("_") and name != "__init__":
            continue
        yield name, obj


def check_callable(qualname, name, fn, errors=True):
    doc = fn.__doc__ or ""
    params, text = parse(doc, name)
    problems = []
    if not text.strip():
        return [f"{qualname}: no docstring"]
    for p in params:
        if not re.search(r"(?<![\w])" + re.escape(p) + r"(?![\w])", text):
            problems.append(f"{qualname}: input '{p}' not named in the docstring")
    if name != "__init__" and not OUTPUT.search(text):
        problems.append(f"{qualname}: no output described")
    if errors and not ERRORS.search(text):
        problems.append(f"{qualname}: no errors described")
    return problems


def collect():
    problems = []
    for name, obj in public():
        if name == "Error" or isinstance(obj, str):
            if not (obj.__doc__ or "").strip():
                problems.append(f"{name}: no docstring")
            continue
        if inspect.isclass(obj):
            cls_doc = obj.__doc__ or ""
            if not cls_doc.strip():
                problems.append(f"{name}: no class docstring")
            for mname, m in members(obj):
                qual = f"{name}.{mname}"
                if isinstance(m, property):
                    if not (m.__doc__ or "").strip():
                        problems.append(f"{qual}: property without a docstring")
                    continue
                fn = getattr(obj, mname)
                if mname == "__init__":
                    # pybind11's __init__ docstring has only the signature: the class docstring must
                    # name the constructor's inputs and its errors
                    params, _ = parse(fn.__doc__ or "", "__init__")
                    for p in params:
                        if not re.search(r"(?<![\w])" + re.escape(p) + r"(?![\w])", cls_doc):
                            problems.append(f"{name}(): input '{p}' not named in the class docstring")
                    if params and not ERRORS.search(cls_doc + (fn.__doc__ or "")):
                        problems.append(f"{name}(): no errors described")
                    continue
                if callable(fn):
                    problems += check_callable(qual, mname, fn, errors=False)
            continue
        if callable(obj):
            problems += check_callable(name, name, obj)
    return problems


def test_every_public_name_is_documented():
    problems = collect()
    assert not problems, "\n".join(problems)


def test_the_checker_catches_a_missing_input():
    """The check itself can fail: a pybind11-style docstring that omits an input is reported."""
    def f():
        pass
    f.__doc__ = "f(V: numpy.ndarray, F: numpy.ndarray, tau: float = 0.5) -> dict\n\nFlows V, F. Output: dict."
    problems = check_callable("f", "f", f)
    assert problems == ["f: input 'tau' not named in the docstring", "f: no errors described"]
