"""The families as the package sees them: rangekit.families() from the C++ registry, one
module each, both following the registration list (families.cmake); and the shared
modules naming none of them."""

import ast
import pathlib
import re

import rangekit
from conftest import samples
from rangekit._families import FAMILIES

SOURCE = pathlib.Path(__file__).resolve().parents[2]


def listed_families():
    """The names of families.cmake's RANGEKIT_FAMILIES, in its order."""
    text = (SOURCE / "families.cmake").read_text()
    code = "\n".join(line.split("#", 1)[0] for line in text.splitlines())
    return tuple(re.search(r"set\(RANGEKIT_FAMILIES\s+([^)]*)\)", code).group(1).split())


def test_families_follow_the_registration_list():
    assert listed_families(), "families.cmake lists no family"
    assert FAMILIES == listed_families()
    assert tuple(family["name"] for family in rangekit.families()) == listed_families()


def test_each_family_has_its_module_binding_and_emulator():
    for name in FAMILIES:
        module = getattr(rangekit, name)
        assert module.__name__ == f"rangekit.{name}"
        assert name in rangekit.__all__
        assert callable(module.open)
        assert hasattr(rangekit._rangekit, name)  # its binding, python/src/<name>/
        assert getattr(rangekit.sim, name).__name__ == name


def test_each_channel_is_a_field_of_the_sample_or_the_record():
    # What families() describes is what the module exposes: every channel key is a Sample
    # property or a column of the NumPy record.
    titles = set()
    for family in rangekit.families():
        assert isinstance(family["title"], str) and family["title"]
        titles.add(family["title"])
        keys = [channel["key"] for channel in family["channels"]]
        assert keys and len(set(keys)) == len(keys)
        for channel in family["channels"]:
            assert set(channel) == {"key", "quantity", "unit", "description"}
            assert hasattr(rangekit.Sample, channel["key"]) or channel["key"] in rangekit.sample_dtype.names
    assert len(titles) == len(FAMILIES)


def channel_of(sample):
    family = next(family for family in rangekit.families() if family["name"] == sample.device)
    return next(channel for channel in family["channels"] if channel["key"] == sample.reading_channel)


def test_a_reading_is_of_one_of_its_familys_channels(ls5_unit):
    read = [rangekit.uls.decode_line(b"$BM,12.345\r")]
    with rangekit.ls5.open(ls5_unit.port) as drv:
        stream = drv.stream(thinning=1)
        read += samples(stream, 3)
        stream.stop()
    read = [sample for sample in read if sample.reading is not None]  # 65534 before a first measurement
    assert {sample.device for sample in read} == set(FAMILIES)
    for sample in read:
        assert sample.device in FAMILIES
        channel = channel_of(sample)
        assert sample.reading_unit == channel["unit"]
        assert channel["quantity"] == "distance"


def names_in_code(path):
    """The identifiers, attributes and string constants of a module, docstrings left out."""
    tree = ast.parse(path.read_text())
    docstrings = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
            body = node.body
            if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant):
                docstrings.add(id(body[0].value))
    for node in ast.walk(tree):
        if isinstance(node, ast.Name):
            yield node.id
        elif isinstance(node, ast.Attribute):
            yield node.attr
        elif isinstance(node, ast.alias):
            yield node.name
        elif isinstance(node, ast.Constant) and isinstance(node.value, str) and id(node) not in docstrings:
            yield node.value


def test_the_shared_modules_name_no_family():
    # A family's code lives in rangekit/<family>.py; the rest reaches it through FAMILIES.
    shared = [path for path in (SOURCE / "python" / "rangekit").glob("*.py") if path.stem not in FAMILIES]
    assert shared
    for path in shared:
        for text in names_in_code(path):
            for name in FAMILIES:
                assert not re.search(rf"\b{name}\b", text), f"{path.name} names the family {name!r}: {text!r}"
