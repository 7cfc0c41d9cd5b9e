"""The typed stubs of a scene's tables (``cohesive_contact/_tables.pyi``) against the scenes and the
parsers, both ways:

1. every key of every scene file under ``scenes/`` is stubbed, under the class its table maps to
   (from ``Scene`` in ``_native.pyi`` through the annotations), with a type its value fits;
2. every stubbed key is accepted by the Rust parsers: a scene with the key added is validated and
   the key is not reported as unknown. A probe key added next to it must be reported as unknown,
   so that a scene the parsers stopped reading before that table cannot pass unnoticed.

The stubs are read with ``ast``; their conventions: a key is an annotated class attribute with its
docstring after it; a table of free names (``fem.boundary``, ``fem.mesh.laws``) has
``__getattr__`` returning the class of its entries; a key that is a Python keyword (``from``) is an
overload ``__getitem__(self, key: Literal["from"]) -> float``.
"""

import ast
import pathlib
import re
from dataclasses import dataclass, field
from typing import Any, Dict, Iterator, List, Optional, Tuple, Union

import pytest

import cohesive_contact as cc

from conftest import SCENES

try:
    import tomllib
except ModuleNotFoundError:  # Python < 3.11
    try:
        import tomli as tomllib  # type: ignore[no-redef]
    except ModuleNotFoundError:
        tomllib = None  # type: ignore[assignment]

PACKAGE = pathlib.Path(__file__).resolve().parents[1] / "cohesive_contact"
TABLES = PACKAGE / "_tables.pyi"
NATIVE = PACKAGE / "_native.pyi"
# every top-level table of a scene
BASE_SCENE = SCENES / "center-crack.toml"
# the name given to an entry of a table of free names (a boundary part, a mesh law)
FREE_NAME = "sample"
# a key no parser knows, put next to the key under test
PROBE = "zz_probe_not_a_key"
SCALARS = ("float", "int", "bool", "str", "Any")


def read_toml(path: pathlib.Path) -> Dict[str, Any]:
    """The TOML file as dicts and lists: tomllib (or tomli), else the package's own reader."""
    if tomllib is not None:
        with open(path, "rb") as f:
            return tomllib.load(f)
    return cc.Scene.from_file(path).to_dict()


# ----------------------------------------------------------------------------------------------
# The stubs, read with ast


@dataclass
class StubClass:
    name: str
    bases: List[str]
    # key -> annotation, in the order of the stub
    keys: Dict[str, ast.expr] = field(default_factory=dict)
    docs: Dict[str, Optional[str]] = field(default_factory=dict)
    # the class of the entries of a table of free names (`__getattr__`'s return)
    free: Optional[ast.expr] = None


def _literal_keys(fn: ast.FunctionDef) -> List[str]:
    """The keys of an overload `__getitem__(self, key: Literal[...])`, else []."""
    args = fn.args.args
    if len(args) != 2 or args[1].annotation is None:
        return []
    k = kind(args[1].annotation)
    return [v for v in k[1] if isinstance(v, str)] if k[0] == "literal" else []


def read_stub_classes(path: pathlib.Path) -> Dict[str, StubClass]:
    classes: Dict[str, StubClass] = {}
    for node in ast.parse(path.read_text(encoding="utf-8")).body:
        if not isinstance(node, ast.ClassDef):
            continue
        c = StubClass(node.name, [b.id for b in node.bases if isinstance(b, ast.Name)])
        for i, stmt in enumerate(node.body):
            if isinstance(stmt, ast.AnnAssign) and isinstance(stmt.target, ast.Name):
                key = stmt.target.id
                nxt = node.body[i + 1] if i + 1 < len(node.body) else None
                doc = None
                if (
                    isinstance(nxt, ast.Expr)
                    and isinstance(nxt.value, ast.Constant)
                    and isinstance(nxt.value.value, str)
                ):
                    doc = nxt.value.value
                c.keys[key], c.docs[key] = stmt.annotation, doc
            elif isinstance(stmt, ast.FunctionDef) and stmt.name == "__getattr__":
                c.free = stmt.returns
            elif isinstance(stmt, ast.FunctionDef) and stmt.name == "__getitem__":
                for key in _literal_keys(stmt):
                    c.keys[key], c.docs[key] = stmt.returns, ast.get_docstring(stmt)
        classes[c.name] = c
    # keys of base classes defined in the same file
    def inherited(name: str) -> Tuple[Dict[str, ast.expr], Dict[str, Optional[str]], Optional[ast.expr]]:
        c = classes[name]
        keys: Dict[str, ast.expr] = {}
        docs: Dict[str, Optional[str]] = {}
        free = None
        for b in c.bases:
            if b in classes:
                k, d, f = inherited(b)
                keys.update(k)
                docs.update(d)
                free = f or free
        keys.update(c.keys)
        docs.update(c.docs)
        return keys, docs, c.free or free

    for name in list(classes):
        c = classes[name]
        c.keys, c.docs, c.free = inherited(name)
    return classes


def kind(ann: Optional[ast.expr]) -> Tuple[str, Any]:
    """An annotation as (kind, detail): ("scalar", "float"), ("table", class name), ("list",
    element annotation), ("dict", value annotation), ("literal", values), ("union", annotations)."""
    if isinstance(ann, ast.Constant) and isinstance(ann.value, str):  # a forward reference
        return kind(ast.parse(ann.value, mode="eval").body)
    if isinstance(ann, ast.Name):
        return ("scalar", ann.id) if ann.id in SCALARS else ("table", ann.id)
    if isinstance(ann, ast.Subscript) and isinstance(ann.value, ast.Name):
        head, arg = ann.value.id, ann.slice
        args = list(arg.elts) if isinstance(arg, ast.Tuple) else [arg]
        if head == "List":
            return ("list", args[0])
        if head == "Dict":
            return ("dict", args[1])
        if head == "Literal":
            return ("literal", [a.value for a in args if isinstance(a, ast.Constant)])
        if head == "Union":
            return ("union", args)
        if head == "Tuple":
            return ("tuple", args)
    raise AssertionError(f"annotation {ast.unparse(ann) if ann else None} is not one the stubs use")


STUBS = read_stub_classes(TABLES)
NATIVE_CLASSES = read_stub_classes(NATIVE)
assert "Scene" in NATIVE_CLASSES, "_native.pyi has no class Scene"
# the scene itself: the root of every table path
CLASSES: Dict[str, StubClass] = {**STUBS, "Scene": NATIVE_CLASSES["Scene"]}
# the classes that are scene tables: the base class of views is not one
TABLE_CLASSES = {n: c for n, c in STUBS.items() if not n.startswith("_")}


def stub_class(name: str, path: str) -> StubClass:
    assert name in CLASSES, f"{path}: annotated as {name}, which no stub defines"
    return CLASSES[name]


# ----------------------------------------------------------------------------------------------
# 1. every key of every scene is stubbed with a type its value fits


def fits(value: Any, ann: ast.expr, path: str, problems: List[str]) -> None:
    """Adds to `problems` every key under `value` that its annotation `ann` does not admit."""
    k, detail = kind(ann)
    shown = ast.unparse(ann)
    if k == "scalar":
        ok = {
            "float": isinstance(value, (int, float)) and not isinstance(value, bool),
            "int": isinstance(value, int) and not isinstance(value, bool),
            "bool": isinstance(value, bool),
            "str": isinstance(value, str),
            "Any": True,
        }[detail]
        if not ok:
            problems.append(f"{path} = {value!r}: stubbed as {shown}")
    elif k == "literal":
        if not any(type(value) is type(v) and value == v for v in detail):
            problems.append(f"{path} = {value!r}: not among the values of {shown}")
    elif k in ("list", "tuple"):
        if not isinstance(value, list):
            problems.append(f"{path} = {value!r}: stubbed as {shown}, not an array")
        elif k == "tuple" and len(value) != len(detail):
            problems.append(f"{path} = {value!r}: stubbed as {shown}")
        else:
            for i, v in enumerate(value):
                fits(v, detail[i] if k == "tuple" else detail, f"{path}[{i}]", problems)
    elif k == "table":
        if not isinstance(value, dict):
            problems.append(f"{path} = {value!r}: stubbed as the table {shown}")
        else:
            table_fits(value, stub_class(detail, path), path, problems)
    elif k == "dict":
        if not isinstance(value, dict):
            problems.append(f"{path} = {value!r}: stubbed as {shown}")
        else:
            for name, v in value.items():
                fits(v, detail, f"{path}.{name}", problems)
    elif k == "union":
        for option in detail:
            found: List[str] = []
            fits(value, option, path, found)
            if not found:
                return
        problems.append(f"{path} = {value!r}: fits no type of {shown}")


def table_fits(table: Dict[str, Any], c: StubClass, path: str, problems: List[str]) -> None:
    for key, value in table.items():
        dotted = f"{path}.{key}" if path else key
        ann = c.keys.get(key, c.free)
        if ann is None:
            problems.append(f"{dotted}: not stubbed (no key {key!r} in class {c.name})")
        else:
            fits(value, ann, dotted, problems)


SCENE_FILES = sorted(SCENES.glob("**/*.toml"))


def test_the_scenes_are_found():
    assert BASE_SCENE in SCENE_FILES and any(p.parent.name == "suite" for p in SCENE_FILES)


@pytest.mark.parametrize("path", SCENE_FILES, ids=[str(p.relative_to(SCENES)) for p in SCENE_FILES])
def test_every_key_of_the_scene_is_stubbed_with_its_type(path):
    problems: List[str] = []
    table_fits(read_toml(path), CLASSES["Scene"], "", problems)
    assert not problems, f"{path.relative_to(SCENES.parent)}:\n  " + "\n  ".join(problems)


# ----------------------------------------------------------------------------------------------
# 2. every stubbed key is accepted by the parsers

Segment = Union[str, int]


def dotted(path: Tuple[Segment, ...]) -> str:
    out = ""
    for s in path:
        out += f"[{s}]" if isinstance(s, int) else (f".{s}" if out else s)
    return out


def leaves(
    c: StubClass, path: Tuple[Segment, ...] = ()
) -> Iterator[Tuple[Tuple[Segment, ...], ast.expr, List[ast.expr]]]:
    """Every key under the class `c` that is not itself a table: (path, annotation, the
    annotations of the tables on the path)."""

    def under(ann: ast.expr, p: Tuple[Segment, ...]):
        k, detail = kind(ann)
        if k == "table":
            for sub, a, ch in leaves(stub_class(detail, dotted(p)), p):
                yield sub, a, [ann] + ch
        elif k == "list" and kind(detail)[0] == "table":  # an array of tables
            for sub, a, ch in leaves(stub_class(kind(detail)[1], dotted(p)), p + (0,)):
                yield sub, a, [ann, detail] + ch
        elif k == "dict" and kind(detail)[0] == "table":
            for sub, a, ch in leaves(stub_class(kind(detail)[1], dotted(p)), p + (FREE_NAME,)):
                yield sub, a, [ann, detail] + ch
        else:
            yield p, ann, []

    for key, ann in c.keys.items():
        yield from under(ann, path + (key,))
    if c.free is not None:
        yield from under(c.free, path + (FREE_NAME,))


def sample(ann: ast.expr, i: int = 0) -> Any:
    """A value of the stubbed type: the first value of a Literal, two elements in an array (a
    pair [x0, x1] is an array of two), every key of a table."""
    k, detail = kind(ann)
    if k == "scalar":
        assert detail != "Any", "a key stubbed as Any cannot be checked"
        return {"float": 0.01 * (i + 1), "int": 1 + i, "bool": False, "str": f"sample{i}"}[detail]
    if k == "literal":
        return detail[i % len(detail)]
    if k == "list":
        return [sample(detail, 0), sample(detail, 1)]
    if k == "tuple":
        return [sample(a, j) for j, a in enumerate(detail)]
    if k == "union":
        return sample(detail[0], i)
    if k == "dict":
        return {FREE_NAME: sample(detail)}
    c = stub_class(detail, "")
    full = {key: sample(a) for key, a in c.keys.items()}
    if not full and c.free is not None:
        full[FREE_NAME] = sample(c.free)
    return full


def descend(container: Any, segment: Segment, ann: ast.expr) -> Any:
    """The table (dict) or array at `segment` of `container`, made from the stub (every key) if the
    scene has none."""
    if isinstance(segment, int):
        if not container:
            container.append(sample(ann))
        return container[segment]
    if segment not in container or not isinstance(container[segment], (dict, list)):
        container[segment] = sample(ann)
    return container[segment]


LEAVES = list(leaves(CLASSES["Scene"]))


def unknown(key: str, message: str) -> bool:
    return re.search(rf"unknown key {re.escape(key)}(?![\w.\[])", message) is not None


@pytest.fixture(scope="module")
def base():
    return cc.Scene.from_file(BASE_SCENE), read_toml(BASE_SCENE)


def _copy(value: Any) -> Any:
    if isinstance(value, dict):
        return {k: _copy(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_copy(v) for v in value]
    return value


def scene_with(base, path: Tuple[Segment, ...], chain: List[ast.expr], value: Any) -> Tuple[str, str]:
    """The base scene with the key at `path` set to `value` (the tables on the path made from the
    stub if the scene has none) and the probe key next to it: the message of its validation
    ("" if valid) and the dotted probe key."""
    scene, tables = base[0].copy(), base[1]
    top = path[0]
    assert isinstance(top, str)
    if len(path) == 1:  # a key of the scene itself (`name`)
        scene[top] = value
        scene[PROBE] = 1
        probe = PROBE
    else:
        table = descend({top: _copy(tables[top])} if top in tables else {}, top, chain[0])
        node = table
        for segment, a in zip(path[1:-1], chain[1:]):
            node = descend(node, segment, a)
        node[path[-1]] = value
        node[PROBE] = 1
        scene[top] = table
        probe = dotted(path[:-1] + (PROBE,))
    try:
        scene.validate()
        return "", probe
    except cc.SceneError as e:
        return str(e), probe


@pytest.mark.parametrize("leaf", LEAVES, ids=[dotted(p) for p, _, _ in LEAVES])
def test_every_stubbed_key_is_accepted_by_the_parsers(leaf, base):
    path, ann, chain = leaf
    message, probe = scene_with(base, path, chain, sample(ann))
    refused = [dotted(path[: n + 1]) for n in range(len(path)) if not isinstance(path[n], int)]
    refused = [k for k in refused if unknown(k, message)]
    assert not refused, f"stubbed but refused by the parsers: {refused}\n{message}"
    assert unknown(probe, message), (
        f"the parsers did not reach the table of {dotted(path)} (the probe key {probe} is not "
        f"reported as unknown): a stubbed type there may not be the parser's\n{message}"
    )


def options(ann: ast.expr) -> Optional[Tuple[List[str], bool]]:
    """The values of a Literal key (or of the elements of an array of them) and whether it is an
    array; None for any other key."""
    k, detail = kind(ann)
    if k == "literal":
        return detail, False
    if k == "list" and kind(detail)[0] == "literal":
        return kind(detail)[1], True
    return None


OPTION_LEAVES = [leaf for leaf in LEAVES if options(leaf[1]) is not None]
NOT_AN_OPTION = "zz_not_an_option"


def refusal(key: str, value: str, message: str) -> Optional[str]:
    """The part of `message` that refuses `value` for `key` (the models' "is not allowed" with the
    allowed values, serde's "unknown variant" with the expected ones), None if it is not refused."""
    v = re.escape(value)
    m = re.search(rf'{re.escape(key)}(?: =|:) "{v}" is not allowed; allowed (.*)', message) or re.search(
        rf"unknown variant `{v}`, expected (.*)", message
    )
    return m.group(1) if m else None


@pytest.mark.parametrize("leaf", OPTION_LEAVES, ids=[dotted(p) for p, _, _ in OPTION_LEAVES])
def test_every_option_of_a_literal_key_is_the_parsers(leaf, base):
    """The Literal's values are the values the parser allows, no more and no fewer."""
    path, ann, chain = leaf
    values, array = options(ann)  # type: ignore[misc]
    key = dotted(path)
    for v in values:
        message, _ = scene_with(base, path, chain, [v] if array else v)
        allowed = refusal(key, v, message)
        # a value allowed only with other keys ("zones" needs zones) is listed in its own refusal
        assert allowed is None or v in quoted(allowed), f"{key} = {v!r} is stubbed but refused:\n{message}"
    message, _ = scene_with(base, path, chain, [NOT_AN_OPTION] if array else NOT_AN_OPTION)
    allowed = refusal(key, NOT_AN_OPTION, message)
    assert allowed is not None, f"{key} = {NOT_AN_OPTION!r} is not refused as an option:\n{message}"
    assert sorted(quoted(allowed)) == sorted(values), f"{key}: the parser allows {allowed!r}, the stub {values}"


TEXT_LEAVES = [leaf for leaf in LEAVES if ast.unparse(leaf[1]) in ("str", "List[str]")]


@pytest.mark.parametrize("leaf", TEXT_LEAVES, ids=[dotted(p) for p, _, _ in TEXT_LEAVES])
def test_a_key_stubbed_as_str_takes_any_text(leaf, base):
    """A string key the parser checks against a fixed set of values is stubbed as a Literal."""
    path, ann, chain = leaf
    value = [NOT_AN_OPTION] if ast.unparse(ann).startswith("List") else NOT_AN_OPTION
    message, _ = scene_with(base, path, chain, value)
    allowed = refusal(dotted(path), NOT_AN_OPTION, message)
    assert allowed is None, f"{dotted(path)} takes only {allowed}: stub it as a Literal\n{message}"


INT_LEAVES = [leaf for leaf in LEAVES if ast.unparse(leaf[1]) == "int"]


@pytest.mark.parametrize("leaf", INT_LEAVES, ids=[dotted(p) for p, _, _ in INT_LEAVES])
def test_a_key_stubbed_as_int_refuses_a_fraction(leaf, base):
    """A key stubbed as int is one the parser reads as an integer (one it reads as a float, which
    takes integers too, is stubbed as float)."""
    path, _, chain = leaf
    message, _ = scene_with(base, path, chain, 0.5)
    assert "invalid type: floating point `0.5`" in message, f"{dotted(path)} takes 0.5: stub it as float\n{message}"


def quoted(text: str) -> List[str]:
    """The values named in an "allowed ..." or "expected ..." text ("all", `fast`)."""
    return sorted({a or b for a, b in re.findall(r'"([^"]*)"|`([^`]*)`', text)})


# ----------------------------------------------------------------------------------------------
# The stubs' own conventions


def test_the_stubs_cover_what_the_scene_imports_and_nothing_unreachable():
    scene = CLASSES["Scene"]
    reached = set()

    def walk(ann: ast.expr) -> None:
        k, detail = kind(ann)
        if k == "table" and detail not in reached:
            reached.add(detail)
            c = stub_class(detail, "")
            for a in list(c.keys.values()) + ([c.free] if c.free is not None else []):
                walk(a)
        elif k in ("list", "dict"):
            walk(detail)
        elif k in ("union", "tuple"):
            for a in detail:
                walk(a)

    for a in scene.keys.values():
        walk(a)
    assert set(TABLE_CLASSES) <= reached, f"stub classes no table path reaches: {set(TABLE_CLASSES) - reached}"


def test_every_stubbed_key_has_a_docstring_ending_with_its_unit():
    missing = []
    for c in TABLE_CLASSES.values():
        for key, ann in c.keys.items():
            doc = (c.docs.get(key) or "").strip()
            k, detail = kind(ann)
            is_table = k == "table" or (k in ("list", "dict") and kind(detail)[0] == "table")
            if not doc or (not is_table and not re.search(r"\[[^\[\]]+\]\.?$", doc)):
                missing.append(f"{c.name}.{key}: {doc!r}")
    assert not missing, "keys without a docstring ending in a unit such as [m]:\n  " + "\n  ".join(missing)


def test_keys_are_typed_as_their_value_not_optional():
    optional = [
        f"{c.name}.{key}: {ast.unparse(ann)}"
        for c in TABLE_CLASSES.values()
        for key, ann in list(c.keys.items()) + ([("__getattr__", c.free)] if c.free is not None else [])
        if re.search(r"\bOptional\b|\bNone\b", ast.unparse(ann))
    ]
    assert not optional, "a key is typed as the value it reads as when present:\n  " + "\n  ".join(optional)
