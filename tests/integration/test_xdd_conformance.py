"""The dictionary of each model covers its vendor XDD: every object and sub-object with the same
data type and access (object-dictionary.md §8.4). Parses the XDD at test time and compares it with
`mcemu --dump-od --model M`; prints the coverage per model and the mcemu additions."""
import json
import os
import subprocess
import unittest
import xml.etree.ElementTree as ET

from mcemu_harness import MCEMU

XDD_DIR = os.environ.get("MCEMU_XDD_DIR", os.path.join(os.path.dirname(__file__), "../../reference/xdd"))
MODELS = {"MC349": "MC349_ETH.xdd", "MC632": "MC6xx_ETH.xdd", "MCFLAT": "MCFLAT_ETH.xdd", "MCN23": "MCN23_ETH.xdd"}
TYPES = {"0001": "BOOLEAN", "0002": "INTEGER8", "0003": "INTEGER16", "0004": "INTEGER32", "0005": "UNSIGNED8",
         "0006": "UNSIGNED16", "0007": "UNSIGNED32", "0009": "VISIBLE_STRING"}
ACCESS_ATTR = {"const": "const", "ro": "ro", "rw": "rw", "wo": "wo"}
ACCESS_PARAM = {"const": "const", "read": "ro", "readWrite": "rw", "readWriteInput": "rw", "readWriteOutput": "rw",
                "write": "wo"}
# Entries where the spec deliberately deviates from the XDD in type or access (object-dictionary.md
# §8.4: none). Format: (model, index, sub): reason.
KNOWN_DEVIATIONS = {}


def xdd_entries(path):
    root = ET.parse(path).getroot()
    for el in root.iter():
        if "}" in el.tag:
            el.tag = el.tag.split("}", 1)[1]
    params = {p.get("uniqueID"): p.get("access") for p in root.iter("parameter")}
    objects, entries = set(), {}

    def access_of(el):
        if el.get("accessType") is not None:
            return ACCESS_ATTR[el.get("accessType")]
        return ACCESS_PARAM[params[el.get("uniqueIDRef")]]

    for obj in root.iter("CANopenObject"):
        index = int(obj.get("index"), 16)
        objects.add(index)
        if obj.get("objectType") == "7":
            entries[(index, 0)] = (TYPES[obj.get("dataType")], access_of(obj))
        for sub in obj.findall("CANopenSubObject"):
            entries[(index, int(sub.get("subIndex"), 16))] = (TYPES[sub.get("dataType")], access_of(sub))
    return objects, entries


def dump(model):
    r = subprocess.run([MCEMU, "--dump-od", "--model", model], capture_output=True, text=True, timeout=30)
    if r.returncode != 0:
        raise AssertionError(r.stderr)
    doc = json.loads(r.stdout)
    assert doc["model"] == model
    return {(e["index"], e["sub"]): e for e in doc["entries"]}


class XddConformance(unittest.TestCase):
    def test_every_xdd_entry_with_same_type_and_access(self):
        report = []
        for model, xdd in MODELS.items():
            objects, entries = xdd_entries(os.path.join(XDD_DIR, xdd))
            od = dump(model)
            od_objects = {i for i, _ in od}
            missing_objects = sorted(objects - od_objects)
            problems = []
            matched = 0
            for key, (dtype, access) in sorted(entries.items()):
                if (model, *key) in KNOWN_DEVIATIONS:
                    continue
                e = od.get(key)
                if e is None:
                    problems.append(f"{key[0]:04X}.{key[1]:02X} missing")
                elif e["type"] != dtype:
                    problems.append(f"{key[0]:04X}.{key[1]:02X} type {e['type']} != XDD {dtype}")
                elif e["access"] != access:
                    problems.append(f"{key[0]:04X}.{key[1]:02X} access {e['access']} != XDD {access}")
                else:
                    matched += 1
            extras = sorted(k for k in od if k not in entries)
            coverage = 100.0 * matched / len(entries)
            report.append(f"{model:7} ({xdd}): {len(objects)} objects, {matched}/{len(entries)} entries "
                          f"= {coverage:.1f} % coverage; {len(extras)} mcemu additions: "
                          + ", ".join(f"{i:04X}.{s:02X}" for i, s in extras))
            with self.subTest(model=model):
                self.assertEqual(missing_objects, [], "objects missing")
                self.assertEqual(problems, [])
                self.assertEqual(coverage, 100.0)
        print("\nXDD coverage:\n  " + "\n  ".join(report))

    def test_presets_sharing_a_base_cover_the_same_xdd(self):
        _, mc349 = xdd_entries(os.path.join(XDD_DIR, "MC349_ETH.xdd"))
        _, mc6xx = xdd_entries(os.path.join(XDD_DIR, "MC6xx_ETH.xdd"))
        _, flat = xdd_entries(os.path.join(XDD_DIR, "MCFLAT_ETH.xdd"))
        for model, entries in (("MC349_AE", mc349), ("MC634", mc6xx), ("MC636", mc6xx), ("PUSHTRACK", mc6xx),
                               ("MCSHORT", flat)):
            od = dump(model)
            with self.subTest(model=model):
                for key, (dtype, access) in entries.items():
                    self.assertIn(key, od)
                    self.assertEqual((od[key]["type"], od[key]["access"]), (dtype, access), key)


if __name__ == "__main__":
    unittest.main()
