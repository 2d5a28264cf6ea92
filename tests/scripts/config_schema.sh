#!/usr/bin/env bash
# The JSON Schemas of osplint.toml and of the macro catalog (schema/, written
# by tools/update-schema) agree with the readers: the repository's files and a
# set of good configurations are accepted by the schema and by
# `osplint config --config FILE`; a set of bad ones are rejected by both (exit
# code 2, the error naming the key). The schemas are valid draft-07 schemas and
# up to date with the rules of the binary.
set -u
osplint=$(realpath "${1:?usage: config_schema.sh path/to/osplint}")
cd "$(dirname "$0")/../.." || exit 2
if ! python3 -c 'import jsonschema, tomllib' 2>/dev/null; then
  echo "not ok: python3 with jsonschema and tomllib is not available (scripts/deps.sh --test installs python3-jsonschema)"
  exit 1
fi
exec python3 - "$osplint" <<'EOF'
import atexit, glob, json, re, shutil, subprocess, sys, tempfile, tomllib
from pathlib import Path
import jsonschema

osplint = sys.argv[1]
failed = False


def report(ok, what, detail=""):
    global failed
    print(("ok: " if ok else "not ok: ") + what + (f" ({detail})" if detail and not ok else ""))
    failed |= not ok


validators = {}
for name in ["osplint", "catalog"]:
    schema = json.loads(Path(f"schema/{name}.schema.json").read_text(encoding="utf-8"))
    try:
        jsonschema.Draft7Validator.check_schema(schema)
        report(True, f"schema/{name}.schema.json is a valid draft-07 schema")
    except jsonschema.SchemaError as e:
        report(False, f"schema/{name}.schema.json is a valid draft-07 schema", e.message)
    validators[name] = jsonschema.Draft7Validator(schema)

r = subprocess.run([sys.executable, "tools/update-schema", "--check", osplint], capture_output=True, text=True)
report(r.returncode == 0, "the schemas are up to date (tools/update-schema --check)", r.stdout.strip())


def schema_errors(kind, text):
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        return [f"not TOML: {e}"]
    return [f"{'.'.join(map(str, e.absolute_path))}: {e.message[:160]}" for e in validators[kind].iter_errors(data)]


# (a) The repository's files.
for path in sorted(glob.glob("examples/**/osplint.toml", recursive=True) + glob.glob("tests/**/osplint.toml", recursive=True)):
    errors = schema_errors("osplint", Path(path).read_text(encoding="utf-8"))
    report(not errors, f"{path} validates", "; ".join(errors[:3]))
catalog_text = Path("data/macros.toml").read_text(encoding="utf-8")
errors = schema_errors("catalog", catalog_text)
report(not errors, "data/macros.toml validates", "; ".join(errors[:3]))

work = Path(tempfile.mkdtemp())
atexit.register(shutil.rmtree, work, True)
(work / "shop").mkdir()
(work / "shop" / "osplint.toml").write_text('[machine]\nunits = "mm"\n')
(work / "project").mkdir()


def osplint_config(text):
    f = work / "project" / "osplint.toml"
    f.write_text(text, encoding="utf-8")
    r = subprocess.run([osplint, "config", "--config", str(f)], capture_output=True, text=True)
    return r.returncode, (r.stdout + r.stderr).strip()


def toml_blocks(path, marker):
    """The ```toml blocks of a document that contain `marker`."""
    text = Path(path).read_text(encoding="utf-8")
    return [b for b in re.findall(r"```toml\n(.*?)```", text, re.S) if marker in b]


# (c) Good configurations: accepted by the schema and by the reader.
good = {
    "the shop macro of docs/catalog.md": toml_blocks("docs/catalog.md", "[macro.OFACE]")[0],
    "the configuration of README.md": toml_blocks("README.md", "[[per-path]]")[0],
    "extend, exclude, per-path rules": '''
extend = "../shop/osplint.toml"
exclude = ["old/**", "*.BAK.MIN", "./tmp/[!a]*"]
[[per-path]]
paths = ["probe/**"]
rules = { OSP204 = "off", OSP1 = "warning", m52-on-call-line = "info" }
[[per-path]]
paths = ["*.SSB"]
''',
    "rule IDs, names, prefixes, any case": '''
[rules]
OSP202 = "off"
m52-on-call-line = "warning"
OSP1 = "info"
OSP00 = "error"
osp101 = "warning"
Syntax-Error = "off"
OSP303 = "info"
''',
    "machine settings": '''
[machine]
units = "inch"
plane = "G19"
distance = "G91"
[machine.travel]
x = [-400, 400.5]
y = [-250.0, 250.0]
z = [-300.0, 150]
[analysis]
explain-unknown = true
''',
    "changing a reading of a shipped macro": '''
[macro.OZAGR.arg.PT]
omitted = "required"
[macro.OLPEX.arg.PK]
omitted = "none"
[macro.OKYLX.arg.PQ]
omitted = "required"
role = "pitch"
''',
    "changing a reading of a shipped fixed cycle (OSP103's note)": '''
[cycle.G83.arg.Q]
sign = "any"
[cycle.G81.arg.Z]
omitted = "none"
[cycle.G85]
replace = true
title = "a shop's own boring cycle"
''',
    "registrations": '''
[codes]
G113 = "OLAPX"
M205 = "OC84L"
M204 = ""
[macro.OG84L]
codes = ["g0115"]
''',
    "a macro with every key": '''
[macro.oshop]
family = "shop"
title = "Shop cycle"
manual = "Shop manual"
source = "p. 4"
forms = ["CALL", "MODIN", "GCODE"]
args_documented = true
units = "any"
g91 = "cycle-axis-absolute"
m52 = "fixed-cycle"
m53 = "undocumented"
hazards = ["g60-ncyl-collision", "repeat-count-abnormal"]
tapping = false
required_scope = "cycle-start"
format = [ { form = "CALL", text = "CALL OSHOP PZ=z PR=r (PK=k)", source = "p. 4" } ]
gcode = { text = "G120 Zz Rr", source = "p. 5", map = { Z = "PZ", r = "pr" }, note = "bare addresses" }
codes = ["G120"]
cancel = "OC84L"
plane_table = "back-counterboring"
common = "back-counterboring"
at_least_one = [ { plane = "g17", args = ["PZ", "PK"], source = "p. 4", inferred = true } ]
relations = [ { left = "PR", op = ">=", right = "PZ+PK+1", plane = "G18", when = "given:PK", inferred = true, source = "p. 4", note = "n" } ]
action = [ { step = "1", text = "To R", feed = "rapid", target = "PR", when = "(M53 or G90) and not given:PK and PZ=-5", inferred = false, source = "p. 6" },
           { step = "2", by = "PK" } ]
notes = [ { text = "Careful", source = "p. 7" } ]
readings = [ { id = "r1", issue = "i", reading = "r", open = true, override = "o" } ]
replace = false
[macro.oshop.arg]
PZ = { meaning = "Z", omitted = "required", default = "error", role = "cycle", axis = ["z", "", "X"], in_format = { CALL = "required", MODIN = "absent" }, source = "p. 4", note = "n", aliases = ["Z1"] }
PR = { omitted = "default", default = 5, default_value = 5, role = "cycle", axis = "cycle", in_format = "optional", sign = "non-negative" }
PK = { omitted = "none", role = "stroke", allowed = [1, 2.5], negative_allowed = true, undocumented = false, always_incremental = true, g91_only = false }
''',
}
for name, text in good.items():
    errors = schema_errors("osplint", text)
    rc, out = osplint_config(text)
    report(not errors and rc == 0, f"good: {name}",
           f"schema: {'; '.join(errors[:3]) or 'accepted'}; osplint config: exit {rc} {out.splitlines()[-1] if rc else ''}")

# (b) Bad configurations: rejected by the schema and by the reader, whose
# error names the key.
NEW = '[macro.OSHOP]\nforms = ["CALL"]\n[macro.OSHOP.arg]\n'
bad = [
    ("an unknown key in [machine]", "[machine]\nspeed = 1\n", "machine.speed"),
    ("an unknown top-level key", "[machines]\nunits = \"mm\"\n", "machines"),
    ("severity \"fatal\"", "[rules]\nOSP101 = \"fatal\"\n", "rules.OSP101"),
    ("an unknown rule", "[rules]\nOSP999 = \"off\"\n", "rules.OSP999"),
    ("a prefix of three letters", "[rules]\nOSP = \"off\"\n", "rules.OSP"),
    ("a prefix in lower case", "[rules]\nosp1 = \"off\"\n", "rules.osp1"),
    ("units \"cm\"", "[machine]\nunits = \"cm\"\n", "machine.units"),
    ("plane in lower case", "[machine]\nplane = \"g17\"\n", "machine.plane"),
    ("distance \"G92\"", "[machine]\ndistance = \"G92\"\n", "machine.distance"),
    ("a travel pair with 3 numbers", "[machine.travel]\nz = [-300.0, 0.0, 150.0]\n", "machine.travel.z"),
    ("a travel with a string", "[machine.travel]\nx = [\"-1\", 1]\n", "machine.travel.x"),
    ("a travel for axis a", "[machine.travel]\na = [-1, 1]\n", "machine.travel.a"),
    ("an empty extend", "extend = \"\"\n", "extend"),
    ("exclude as a string", "exclude = \"old/**\"\n", "exclude"),
    ("per-path without paths", "[[per-path]]\nrules = { OSP1 = \"off\" }\n", "per-path.paths"),
    ("per-path with empty paths", "[[per-path]]\npaths = []\n", "per-path.paths"),
    ("an unknown key in per-path", "[[per-path]]\npaths = [\"a\"]\nrule = { OSP1 = \"off\" }\n", "per-path.rule"),
    ("per-path with severity \"fatal\"", "[[per-path]]\npaths = [\"a\"]\nrules = { OSP1 = \"fatal\" }\n", "per-path.rules.OSP1"),
    ("explain-unknown = \"yes\"", "[analysis]\nexplain-unknown = \"yes\"\n", "analysis.explain-unknown"),
    ("a control's own G code registered", "[codes]\nG81 = \"OLAPX\"\n", "codes.G81"),
    ("a G01 registered", "[codes]\nG01 = \"OLAPX\"\n", "codes.G01"),
    ("a code in lower case registered", "[codes]\ng115 = \"OLAPX\"\n", "codes.g115"),
    ("the schema-1 table [macros.gcode]", "[macros.gcode]\nG113 = \"OLAPX\"\n", "macros"),
    ("an unknown argument key in a shop macro", NEW + "PZ = { omitted = \"required\", role = \"cycle\", omited = \"none\" }\n", "macro.OSHOP.arg.PZ.omited"),
    ("omitted = \"maybe\"", NEW + "PZ = { omitted = \"maybe\", role = \"cycle\" }\n", "macro.OSHOP.arg.PZ.omitted"),
    ("role \"angle\"", NEW + "PZ = { omitted = \"none\", role = \"angle\" }\n", "macro.OSHOP.arg.PZ.role"),
    ("axis \"diagonal\"", NEW + "PZ = { omitted = \"none\", role = \"cycle\", axis = \"diagonal\" }\n", "macro.OSHOP.arg.PZ.axis"),
    ("an axis list of two", NEW + "PZ = { omitted = \"none\", role = \"cycle\", axis = [\"Z\", \"Y\"] }\n", "macro.OSHOP.arg.PZ.axis"),
    ("axis W", NEW + "PZ = { omitted = \"none\", role = \"cycle\", axis = [\"Z\", \"Y\", \"W\"] }\n", "macro.OSHOP.arg.PZ.axis"),
    ("in_format for an unknown form", NEW + "PZ = { omitted = \"none\", role = \"cycle\", in_format = { CAL = \"required\" } }\n", "macro.OSHOP.arg.PZ.in_format.CAL"),
    ("sign \"negative\"", NEW + "PZ = { omitted = \"none\", role = \"cycle\", sign = \"negative\" }\n", "macro.OSHOP.arg.PZ.sign"),
    ("allowed as strings", NEW + "PZ = { omitted = \"none\", role = \"cycle\", allowed = [\"1\"] }\n", "macro.OSHOP.arg.PZ.allowed"),
    ("a default that is a boolean", NEW + "PZ = { omitted = \"default\", role = \"cycle\", default = true }\n", "macro.OSHOP.arg.PZ.default"),
    ("an argument name with a dash", NEW + "P-Z = { omitted = \"none\", role = \"cycle\" }\n", "macro.OSHOP.arg.P-Z"),
    ("a macro not named O...", "[macro.SHOP]\nforms = [\"CALL\"]\n", "macro.SHOP"),
    ("an unknown macro key", "[macro.OSHOP]\nforms = [\"CALL\"]\nmm = true\n", "macro.OSHOP.mm"),
    ("units \"inch\"", "[macro.OSHOP]\nforms = [\"CALL\"]\nunits = \"inch\"\n", "macro.OSHOP.units"),
    ("g91 \"absolute\"", "[macro.OSHOP]\nforms = [\"CALL\"]\ng91 = \"absolute\"\n", "macro.OSHOP.g91"),
    ("an unknown hazard", "[macro.OSHOP]\nforms = [\"CALL\"]\nhazards = [\"g60\"]\n", "macro.OSHOP.hazards"),
    ("a hazard twice", "[macro.OSHOP]\nforms = [\"CALL\"]\nhazards = [\"repeat-count-abnormal\", \"repeat-count-abnormal\"]\n", "macro.OSHOP.hazards"),
    ("the schema-1 key mm_only", "[macro.OSHOP]\nforms = [\"CALL\"]\nmm_only = true\n", "macro.OSHOP.mm_only"),
    ("the schema-1 key g60_ncyl_forbidden", "[macro.OZAGR]\ng60_ncyl_forbidden = false\n", "macro.OZAGR.g60_ncyl_forbidden"),
    ("form \"CALLS\"", "[macro.OSHOP]\nforms = [\"CALLS\"]\n", "macro.OSHOP.forms"),
    ("m53 \"return\"", "[macro.OSHOP]\nforms = [\"CALL\"]\nm53 = \"return\"\n", "macro.OSHOP.m53"),
    ("required_scope \"once\"", "[macro.OSHOP]\nforms = [\"CALL\"]\nrequired_scope = \"once\"\n", "macro.OSHOP.required_scope"),
    ("a format line without text", "[macro.OSHOP]\nforms = [\"CALL\"]\nformat = [ { form = \"CALL\" } ]\n", "macro.OSHOP.format[0].text"),
    ("a gcode form without text", "[macro.OSHOP]\nforms = [\"CALL\"]\ngcode = { source = \"p. 1\" }\n", "macro.OSHOP.gcode.text"),
    ("a code of the control", "[macro.OSHOP]\nforms = [\"CALL\"]\ncodes = [\"M30\"]\n", "macro.OSHOP.codes"),
    ("a code that is not one", "[macro.OSHOP]\nforms = [\"CALL\"]\ncodes = [\"X115\"]\n", "macro.OSHOP.codes"),
    ("at_least_one with one argument", NEW + "PZ = { omitted = \"none\", role = \"cycle\" }\n[macro.OSHOP2]\nforms = [\"CALL\"]\nat_least_one = [ { args = [\"PZ\"] } ]\n", "macro.OSHOP2.at_least_one[0].args"),
    ("relation op =>", "[macro.OSHOP]\nforms = [\"CALL\"]\nrelations = [ { left = \"1\", op = \"=>\", right = \"2\" } ]\n", "macro.OSHOP.relations[0].op"),
    ("relation plane G20", "[macro.OSHOP]\nforms = [\"CALL\"]\nrelations = [ { left = \"1\", op = \">\", right = \"2\", plane = \"G20\" } ]\n", "macro.OSHOP.relations[0].plane"),
    ("an action step without step", "[macro.OSHOP]\nforms = [\"CALL\"]\naction = [ { text = \"go\" } ]\n", "macro.OSHOP.action[0].step"),
    ("a note without text", "[macro.OSHOP]\nforms = [\"CALL\"]\nnotes = [ { source = \"p. 1\" } ]\n", "macro.OSHOP.notes[0].text"),
    ("a reading without id", "[macro.OSHOP]\nforms = [\"CALL\"]\nreadings = [ { reading = \"r\" } ]\n", "macro.OSHOP.readings[0].id"),
    ("an unknown key in a reading", "[macro.OSHOP]\nforms = [\"CALL\"]\nreadings = [ { id = \"a\", reading = \"r\", closed = true } ]\n", "macro.OSHOP.readings[0].closed"),
    ("a fixed cycle named by an M code", "[cycle.M81]\ntitle = \"t\"\n", "cycle.M81"),
]
for name, text, key in bad:
    errors = schema_errors("osplint", text)
    rc, out = osplint_config(text)
    names_key = f"'{key}'" in out
    report(bool(errors) and rc == 2 and names_key, f"bad: {name}",
           f"schema: {'rejects' if errors else 'accepts'}; osplint config: exit {rc}: {out.splitlines()[-1] if out else ''}")

# The catalog: what a new macro, cycle or argument needs, and its own tables.
catalog_bad = [
    ("an argument without role", "[macro.OSHOP]\nforms = [\"CALL\"]\narg = { PZ = { omitted = \"none\" } }\n"),
    ("a macro without forms", "[macro.OSHOP]\ntitle = \"t\"\n"),
    ("omitted = \"default\" without default", "[cycle.G81.arg]\nZ = { omitted = \"default\", role = \"cycle\" }\n"),
    ("a fixed cycle named by an M code", "[cycle.M81]\ntitle = \"t\"\n"),
    ("schema 1", "schema = 1\n"),
    ("an unknown key in a plane table", "[plane_table.x]\nrows = []\n"),
    ("an unknown key in common rules", "[common.x]\nnote = \"n\"\n"),
]
for name, text in catalog_bad:
    report(bool(schema_errors("catalog", text)), f"bad catalog: {name}")
report(not schema_errors("catalog", catalog_text + "\n[macro.OSHOP]\nforms = [\"CALL\"]\narg = { PZ = { omitted = \"default\", default = \"1\", role = \"cycle\" } }\n"),
       "good catalog: a macro added to data/macros.toml")

sys.exit(1 if failed else 0)
EOF
