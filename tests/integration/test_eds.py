"""EDS-01 (slcan-canopen.md §12): for every preset, `mcemu --dump-eds` prints a CiA 306 EDS that
Python's configparser reads (also the way python-canopen reads it: RawConfigParser with ';' inline
comments) and that lists exactly the dictionary of `--dump-od` — index, sub-index, data type,
access, default — with the sections [FileInfo], [DeviceInfo], [MandatoryObjects],
[OptionalObjects] and [ManufacturerObjects] complete. python-canopen itself is not a Debian
package; where `import canopen` works, `canopen.import_od` must load the file as well."""
import configparser
import os
import re
import subprocess
import tempfile
import unittest

from mcemu_harness import MCEMU
from test_slcan import dump

PRESETS = ("MC349", "MC349_AE", "MCN23", "MCFLAT", "MCSHORT", "MC632", "MC634", "MC636", "PUSHTRACK")
TYPES = {"BOOLEAN": 0x1, "INTEGER8": 0x2, "INTEGER16": 0x3, "INTEGER32": 0x4, "UNSIGNED8": 0x5,
         "UNSIGNED16": 0x6, "UNSIGNED32": 0x7, "VISIBLE_STRING": 0x9}


def eds_text(model):
    r = subprocess.run([MCEMU, "--dump-eds", "--model", model], capture_output=True, text=True, timeout=30)
    assert r.returncode == 0, r.stderr
    assert r.stderr == "", r.stderr
    return r.stdout


def parse(text, raw=False):
    p = configparser.RawConfigParser(inline_comment_prefixes=(";",)) if raw else configparser.ConfigParser()
    p.optionxform = str
    p.read_string(text)
    return p


def section_of(index, sub, compound):
    return f"{index:04X}sub{sub:X}" if compound else f"{index:04X}"


class Eds(unittest.TestCase):
    def test_eds01_every_preset_lists_its_dictionary(self):
        for model in PRESETS:
            with self.subTest(model=model):
                text = eds_text(model)
                entries = dump(model)
                for raw in (False, True):
                    self.check(parse(text, raw), entries, model)

    def check(self, eds, entries, model):
        for s in ("FileInfo", "DeviceInfo", "MandatoryObjects", "OptionalObjects", "ManufacturerObjects",
                  "DummyUsage", "Comments"):
            self.assertIn(s, eds.sections())
        info = eds["FileInfo"]
        for key in ("FileName", "FileVersion", "FileRevision", "EDSVersion", "Description", "CreationTime",
                    "CreationDate", "CreatedBy", "ModificationTime", "ModificationDate", "ModifiedBy"):
            self.assertTrue(info.get(key), key)
        self.assertEqual(info["EDSVersion"], "4.0")
        self.assertRegex(info["CreationDate"], r"^\d\d-\d\d-\d{4}$")
        self.assertRegex(info["CreationTime"], r"^\d\d:\d\d(AM|PM)$")
        device = eds["DeviceInfo"]
        by_key = {(e["index"], e["sub"]): e for e in entries}
        self.assertEqual(int(device["VendorNumber"], 0), by_key[(0x1018, 1)]["value"])
        self.assertEqual(int(device["ProductNumber"], 0), by_key[(0x1018, 2)]["value"])
        self.assertEqual(device["ProductName"], by_key[(0x1008, 0)]["value"])
        self.assertEqual(device["Granularity"], "0")
        self.assertEqual(int(device["NrOfRXPDO"]), len({i for i, _ in by_key if 0x1400 <= i <= 0x15FF}))
        self.assertEqual(int(device["NrOfTXPDO"]), len({i for i, _ in by_key if 0x1800 <= i <= 0x19FF}))

        # the object lists: every index once, in the group CiA 306 puts it in
        listed = {}
        for group in ("MandatoryObjects", "OptionalObjects", "ManufacturerObjects"):
            g = eds[group]
            n = int(g["SupportedObjects"])
            indices = [int(g[str(i)], 0) for i in range(1, n + 1)]
            self.assertEqual(len(g), n + 1, f"{group}: no extra keys")
            for index in indices:
                self.assertNotIn(index, listed)
                listed[index] = group
        indices = {i for i, _ in by_key}
        self.assertEqual(set(listed), indices, model)
        self.assertEqual({i for i, g in listed.items() if g == "MandatoryObjects"}, {0x1000, 0x1001, 0x1018})
        self.assertEqual({i for i, g in listed.items() if g == "ManufacturerObjects"},
                         {i for i in indices if 0x2000 <= i <= 0x5FFF})

        # every entry, with type, access and default; nothing else
        subs_of = {}
        for (index, sub) in by_key:
            subs_of.setdefault(index, []).append(sub)
        object_sections = {s for s in eds.sections() if re.match(r"^[0-9A-F]{4}(sub[0-9A-F]+)?$", s)}
        expected_sections = set()
        for index, subs in subs_of.items():
            head = eds[f"{index:04X}"]
            compound = int(head["ObjectType"], 0) in (8, 9)
            expected_sections.add(f"{index:04X}")
            if compound:
                self.assertEqual(int(head["SubNumber"]), len(subs), f"{index:04X}h")
            else:
                self.assertEqual(subs, [0], f"{index:04X}h is a VAR")
            for sub in subs:
                e = by_key[(index, sub)]
                name = section_of(index, sub, compound)
                expected_sections.add(name)
                s = eds[name]
                where = f"{model} [{name}]"
                self.assertEqual(int(s["ObjectType"], 0), 7, where)
                self.assertEqual(int(s["DataType"], 0), TYPES[e["type"]], where)
                self.assertEqual(s["AccessType"], e["access"], where)
                self.assertEqual(s["PDOMapping"], "0" if e["pdo"] == "no" else "1", where)
                if e["type"] == "VISIBLE_STRING":
                    self.assertEqual(s.get("DefaultValue", ""), e["value"], where)
                else:
                    self.assertEqual(int(s["DefaultValue"], 0), e["value"], where)
                if "min" in e:
                    self.assertEqual(int(s["LowLimit"], 0), e["min"], where)
                    self.assertEqual(int(s["HighLimit"], 0), e["max"], where)
                self.assertEqual(s["ParameterName"], e["name"].replace(";", ","), where)  # ';' starts a comment
        self.assertEqual(object_sections, expected_sections, model)

    def test_config_objects_change_the_defaults(self):
        with tempfile.TemporaryDirectory() as d:
            cfg = os.path.join(d, "c.json")
            with open(cfg, "w") as f:
                f.write('{"objects": {"6083.00": 2500}}')
            r = subprocess.run([MCEMU, "--dump-eds", "--config", cfg], capture_output=True, text=True, timeout=30)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertEqual(int(parse(r.stdout)["6083"]["DefaultValue"], 0), 2500)

    def test_fleet_dumps_the_drive_named_by_drive(self):
        """--dump-eds/--dump-od honour --fleet: --drive K dumps drive K (its model and its config);
        a process of more than one drive without --drive is a usage error naming --drive."""
        with tempfile.TemporaryDirectory() as d:
            fleet = os.path.join(d, "fleet.json")
            with open(fleet, "w") as f:
                f.write('[{"model": "MC349"}, {"model": "MCFLAT", "objects": {"6083.00": 2500}}]')
            r = subprocess.run([MCEMU, "--dump-eds", "--fleet", fleet, "--drive", "2"], capture_output=True,
                               text=True, timeout=30)
            self.assertEqual(r.returncode, 0, r.stderr)
            eds = parse(r.stdout)
            self.assertEqual(eds["FileInfo"]["FileName"], "MCFLAT.eds")
            self.assertEqual(int(eds["6083"]["DefaultValue"], 0), 2500)
            r = subprocess.run([MCEMU, "--dump-eds", "--fleet", fleet, "--drive=1"], capture_output=True,
                               text=True, timeout=30)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertEqual(parse(r.stdout)["FileInfo"]["FileName"], "MC349.eds")
            self.assertEqual(int(parse(r.stdout)["6083"]["DefaultValue"], 0), 1000)
            r = subprocess.run([MCEMU, "--dump-od", "--fleet", fleet, "--drive", "2"], capture_output=True,
                               text=True, timeout=30)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertIn('"MCFLAT"', r.stdout)
            for args, needle in ((["--dump-eds", "--fleet", fleet], "--drive K"),
                                 (["--dump-eds", "--drives", "3"], "--drive K"),
                                 (["--dump-eds", "--fleet", fleet, "--drive", "3"], "has 2 drives"),
                                 (["--fleet", fleet, "--drive", "2"], "--dump-od or --dump-eds")):
                r = subprocess.run([MCEMU] + args, capture_output=True, text=True, timeout=30)
                self.assertEqual(r.returncode, 2, args)
                self.assertEqual(r.stdout, "", args)
                self.assertIn(needle, r.stderr, args)

    def test_python_canopen_imports_it_where_available(self):
        try:
            import canopen  # noqa: F401 - not a Debian package (slcan-canopen.md §12 EDS-01)
        except ImportError:
            self.skipTest("python-canopen is not installed (not in Debian 12); configparser checks ran instead")
        with tempfile.TemporaryDirectory() as d:
            for model in PRESETS:
                path = os.path.join(d, model + ".eds")
                with open(path, "w") as f:
                    f.write(eds_text(model))
                od = canopen.import_od(path)
                self.assertEqual(od[0x6041].data_type, 0x6)
                self.assertEqual(len(od[0x1018]), 5)


if __name__ == "__main__":
    unittest.main()
