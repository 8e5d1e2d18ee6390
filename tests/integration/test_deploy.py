"""docker/ and deploy/k8s/ agree with mcemu's command line (issue 13 item 4).

No container engine or cluster runs here, so the files are parsed (Debian's python3-yaml) and
checked against the real binary: every flag they pass exists in `mcemu --help`; the ports they
declare are the defaults `--help` names, in the Dockerfile's EXPOSE, the compose files, the pod
and the Service; the state volume is where the ENTRYPOINT puts the state directory; each service's
command line, run by the real mcemu, starts a drive that reports the --ip it was given; the probe
path and the compose healthcheck are answered by a running mcemu.
"""
import glob
import ipaddress
import json
import os
import re
import socket
import subprocess
import tempfile
import unittest

import yaml

from mcemu_harness import MCEMU, Mcemu

ROOT = os.path.normpath(os.path.join(os.path.dirname(__file__), "../.."))
SERVICES = {"refgo": "tcp", "slcan": "tcp", "http": "tcp", "udp": "udp", "faulhaber": "tcp"}


def read(relative):
    with open(os.path.join(ROOT, relative)) as f:
        return f.read()


def help_text():
    return subprocess.run([MCEMU, "--help"], capture_output=True, text=True, timeout=20, check=True).stdout


HELP = help_text()
FLAGS = set(re.findall(r"^\s+(--[a-z][a-z-]*)", HELP, re.M))
DEFAULT_PORTS = {s: int(re.search(rf"--{s}-port N .*?\(default (\d+)", HELP).group(1)) for s in SERVICES}


def dockerfile():
    """The image's stage of docker/Dockerfile: ENTRYPOINT, EXPOSE, USER, VOLUME, uid and gid. The final
    stage may start FROM an earlier stage of the file (FROM runtime): its text counts as well."""
    text = read("docker/Dockerfile").replace("\\\n", " ")
    stages = re.split(r"^(?=FROM )", text, flags=re.M)[1:]
    by_name = {m.group(1): st for st in stages if (m := re.match(r"FROM \S+ AS (\S+)", st))}
    final = stages[-1]
    base = re.match(r"FROM (\S+)", final).group(1)
    if base in by_name:
        final = by_name[base] + final
    out = {"entrypoint": json.loads(re.search(r"^ENTRYPOINT (\[.*\])$", final, re.M).group(1)),
           "expose": set(re.search(r"^EXPOSE (.*)$", final, re.M).group(1).split()),
           "user": re.search(r"^USER (\S+)$", final, re.M).group(1),
           "volume": json.loads(re.search(r"^VOLUME (\[.*\])$", final, re.M).group(1)),
           "uid": int(re.search(r"useradd [^&]*--uid (\d+)", final).group(1)),
           "gid": int(re.search(r"groupadd [^&]*--gid (\d+)", final).group(1))}
    return out


DOCKER = dockerfile()


def flag_value(args, flag):
    values = [args[i + 1] for i, a in enumerate(args) if a == flag]
    return values[-1] if values else None


def assert_flags_exist(tc, args, where):
    for a in args:
        if a.startswith("--"):
            tc.assertIn(a, FLAGS, f"{where}: {a} is not an option of mcemu --help")


def assert_starts_as(tc, args, ip, model, where):
    """Runs the real mcemu with `args` (the container's command line without the binary), then
    bound to 127.0.0.1 on free ports with a temp state dir (the last of a repeated flag wins), and
    checks the IP address and model the drive reports."""
    with tempfile.TemporaryDirectory() as tmp:
        overrides = ["--bind", "127.0.0.1", "--state-dir", tmp] + [x for s in SERVICES for x in (f"--{s}-port", "0")]
        with Mcemu(*args, *overrides, ports_zero=False) as m:
            status, body = m.http("GET", "/api/v1/info")
            tc.assertEqual(status, 200, where)
            info = json.loads(body)
            tc.assertEqual((info["ip"], info["model"]), (ip, model), where)


class CommandLines(unittest.TestCase):
    def test_the_help_text_names_every_port_default(self):
        self.assertEqual(DEFAULT_PORTS, {"refgo": 10001, "slcan": 15001, "http": 80, "udp": 14999, "faulhaber": 10002})

    def test_dockerfile(self):
        self.assertEqual(DOCKER["expose"], {f"{DEFAULT_PORTS[s]}/{p}" for s, p in SERVICES.items()})
        entry = DOCKER["entrypoint"]
        self.assertEqual(entry[0], "/usr/local/bin/mcemu")
        assert_flags_exist(self, entry[1:], "ENTRYPOINT")
        self.assertEqual(flag_value(entry, "--bind"), "0.0.0.0")
        self.assertEqual(DOCKER["volume"], [flag_value(entry, "--state-dir")])
        self.assertNotIn(DOCKER["user"], ("root", "0"))
        self.assertEqual(DOCKER["uid"], DOCKER["gid"])

    def test_compose_one_drive(self):
        doc = yaml.safe_load(read("docker/compose.yml"))
        drive = doc["services"]["drive"]
        assert_flags_exist(self, drive["command"], "compose.yml")
        container_ports = {p.split(":")[-1] for p in drive["ports"]}
        self.assertEqual(container_ports, {f"{DEFAULT_PORTS[s]}/{p}" for s, p in SERVICES.items()})
        self.assertEqual([v.split(":")[1] for v in drive["volumes"]], DOCKER["volume"])
        assert_starts_as(self, DOCKER["entrypoint"][1:] + drive["command"], flag_value(drive["command"], "--ip"),
                              flag_value(drive["command"], "--model"), "compose.yml")

    def test_compose_fleet_each_drive_its_own_address(self):
        doc = yaml.safe_load(read("docker/compose.fleet.yml"))
        drives = doc["services"]
        self.assertGreaterEqual(len(drives), 2)
        subnet = ipaddress.ip_network(doc["networks"]["machine"]["ipam"]["config"][0]["subnet"])
        addresses, volumes = set(), set()
        for name, svc in drives.items():
            where = f"compose.fleet.yml {name}"
            cmd = svc["command"]
            assert_flags_exist(self, cmd, where)
            address = svc["networks"]["machine"]["ipv4_address"]
            self.assertEqual(flag_value(cmd, "--ip"), address, f"{where}: --ip is the container's own address")
            self.assertIn(ipaddress.ip_address(address), subnet, where)
            addresses.add(address)
            self.assertNotIn("ports", svc, f"{where}: drives keep the default ports on their own address")
            self.assertNotIn("--bind", cmd, f"{where}: the ENTRYPOINT binds 0.0.0.0")
            self.assertFalse({f for f in cmd if f.endswith("-port")}, f"{where}: default ports")
            self.assertEqual(svc["sysctls"]["net.ipv4.ip_unprivileged_port_start"], 0, where)
            (volume,) = svc["volumes"]
            source, target = volume.split(":")
            self.assertEqual([target], DOCKER["volume"], where)
            volumes.add(source)
            self.assertIn(source, doc["volumes"], where)
            assert_starts_as(self, DOCKER["entrypoint"][1:] + cmd, address, flag_value(cmd, "--model"), where)
        self.assertEqual(len(addresses), len(drives), "one address per drive")
        self.assertEqual(len(volumes), len(drives), "one state volume per drive")

    def test_compose_healthcheck_against_a_running_drive(self):
        doc = yaml.safe_load(read("docker/compose.fleet.yml"))
        for name, svc in doc["services"].items():
            test = svc["healthcheck"]["test"]
            self.assertEqual(test[:3], ["CMD", "bash", "-c"], name)
            script = test[3]
            self.assertIn(f"/dev/tcp/127.0.0.1/{DEFAULT_PORTS['http']}", script, name)
        with Mcemu() as m:
            port = m.ports["http"]
            ok = subprocess.run(["bash", "-c", script.replace("/127.0.0.1/80", f"/127.0.0.1/{port}")], timeout=10)
            self.assertEqual(ok.returncode, 0, "the healthcheck passes against a running mcemu")
        with socket.socket() as s:  # a port nobody listens on once this socket is closed
            s.bind(("127.0.0.1", 0))
            free = s.getsockname()[1]
        down = subprocess.run(["bash", "-c", script.replace("/127.0.0.1/80", f"/127.0.0.1/{free}")], timeout=10,
                              stdin=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        self.assertNotEqual(down.returncode, 0, "and fails where no drive answers")


class Kubernetes(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.docs = {}
        for path in sorted(glob.glob(os.path.join(ROOT, "deploy/k8s/*.yaml"))):
            for doc in yaml.safe_load_all(read(path)):
                cls.docs[(doc["kind"], doc["metadata"]["name"] if "metadata" in doc else None)] = (os.path.basename(path),
                                                                                                     doc)
        cls.sts = next(d for (k, _), (_, d) in cls.docs.items() if k == "StatefulSet")
        cls.svc = next(d for (k, _), (_, d) in cls.docs.items() if k == "Service")
        cls.pod = cls.sts["spec"]["template"]["spec"]
        (cls.container,) = cls.pod["containers"]

    def test_kustomization_lists_every_manifest(self):
        kustomization = next(d for (k, _), (_, d) in self.docs.items() if k == "Kustomization")
        files = {f for f, d in self.docs.values() if d["kind"] != "Kustomization"}
        self.assertEqual(set(kustomization["resources"]), files)

    def test_headless_service_selects_the_pods(self):
        self.assertEqual(self.svc["spec"]["clusterIP"], "None")
        self.assertEqual(self.sts["spec"]["serviceName"], self.svc["metadata"]["name"])
        labels = self.sts["spec"]["template"]["metadata"]["labels"]
        self.assertLessEqual(self.svc["spec"]["selector"].items(), labels.items())
        self.assertLessEqual(self.sts["spec"]["selector"]["matchLabels"].items(), labels.items())

    def test_ports_are_the_drive_defaults(self):
        ports = {p["name"]: (p["containerPort"], p["protocol"]) for p in self.container["ports"]}
        self.assertEqual(ports, {s: (DEFAULT_PORTS[s], p.upper()) for s, p in SERVICES.items()})
        for p in self.svc["spec"]["ports"]:
            container_port, protocol = ports[p["targetPort"]]
            self.assertEqual((p["port"], p["protocol"]), (container_port, protocol), p["name"])
        self.assertEqual({p["name"] for p in self.svc["spec"]["ports"]}, set(SERVICES))

    def test_probes_get_info_on_port_80_and_mcemu_answers_it(self):
        ports = {p["name"]: p["containerPort"] for p in self.container["ports"]}
        paths = set()
        for probe in ("livenessProbe", "readinessProbe"):
            get = self.container[probe]["httpGet"]
            port = ports.get(get["port"], get["port"])
            self.assertEqual(port, DEFAULT_PORTS["http"], probe)
            paths.add(get["path"])
        self.assertEqual(paths, {"/api/v1/info"})
        with Mcemu() as m:
            status, body = m.http("GET", "/api/v1/info")
            self.assertEqual(status, 200)
            self.assertEqual(json.loads(body)["emulator"], "mcemu")

    def test_pod_ip_is_the_drive_ip(self):
        args = self.container["args"]
        self.assertEqual(flag_value(args, "--ip"), "$(POD_IP)")
        env = {e["name"]: e for e in self.container["env"]}
        self.assertEqual(env["POD_IP"]["valueFrom"]["fieldRef"]["fieldPath"], "status.podIP")
        self.assertIsNone(self.container.get("command"), "the image's ENTRYPOINT (bind, state dir) stays")
        # $(VAR) as Kubernetes expands it, then the command line through the real binary.
        expanded = [a.replace("$(POD_IP)", "10.244.1.7") for a in args]
        assert_flags_exist(self, args, "statefulset args")
        assert_starts_as(self, DOCKER["entrypoint"][1:] + expanded, "10.244.1.7",
                                      flag_value(args, "--model"), "statefulset")

    def test_state_on_a_claim_per_pod(self):
        mounts = {m["name"]: m for m in self.container["volumeMounts"]}
        self.assertEqual(set(mounts), {"state", "tmp"})
        mount = mounts["state"]
        (claim,) = self.sts["spec"]["volumeClaimTemplates"]
        self.assertEqual(mount["name"], claim["metadata"]["name"])
        self.assertEqual([mount["mountPath"]], DOCKER["volume"])
        self.assertEqual(claim["spec"]["accessModes"], ["ReadWriteOnce"])

    def test_writable_tmp_for_the_script_engine(self):
        # readOnlyRootFilesystem: the engine makes an empty working directory per run under /tmp
        self.assertIs(self.container["securityContext"]["readOnlyRootFilesystem"], True)
        tmp = next(m for m in self.container["volumeMounts"] if m["name"] == "tmp")
        self.assertEqual(tmp["mountPath"], "/tmp")
        (volume,) = [v for v in self.pod["volumes"] if v["name"] == "tmp"]
        self.assertIn("emptyDir", volume)

    def test_non_root_as_the_image_user(self):
        sc = self.pod["securityContext"]
        self.assertIs(sc["runAsNonRoot"], True)
        self.assertEqual((sc["runAsUser"], sc["runAsGroup"], sc["fsGroup"]), (DOCKER["uid"], DOCKER["gid"], DOCKER["gid"]))
        sysctls = {s["name"]: s["value"] for s in sc["sysctls"]}
        self.assertEqual(sysctls["net.ipv4.ip_unprivileged_port_start"], "0")
        csc = self.container["securityContext"]
        self.assertIs(csc["allowPrivilegeEscalation"], False)
        self.assertIs(csc["readOnlyRootFilesystem"], True)  # ./tools/dev image runs the image so
        self.assertEqual(csc["capabilities"]["drop"], ["ALL"])


if __name__ == "__main__":
    unittest.main()
