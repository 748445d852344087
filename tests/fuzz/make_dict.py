"""Writes the TOML fuzz targets' dictionary (tests/fuzz/dict/toml.dict) from the resolved
scenario that `plumetrace config` prints: every table, dotted key and choice, with the sweep
file's keys and TOML's own tokens. Usage: make_dict.py RESOLVED.toml OUT.dict"""
import re
import sys


def entry(word: str) -> str:
    """A libFuzzer dictionary line: the word quoted, with \\, " and bytes outside ASCII escaped."""
    out = ""
    for ch in word:
        if ch in '\\"':
            out += "\\" + ch
        elif 32 <= ord(ch) < 127:
            out += ch
        else:
            out += "".join(f"\\x{b:02X}" for b in ch.encode())
    return f'"{out}"'


words = []
table = ""
for line in open(sys.argv[1]):
    line = line.split("#")[0].strip()
    if m := re.fullmatch(r"\[(\w+)\]", line):
        table = m.group(1)
        words += [f"[{table}]", table + "."]
    elif m := re.fullmatch(r"(\w+) = (.*)", line):
        words += [f"{table}.{m.group(1)}=", m.group(1) + " = "]
        if m.group(2).startswith('"'):
            words.append(m.group(2))
# sweep files, the --set separator, numbers at the edges, TOML syntax
words += ["name = ", "title = ", "scenario = ", "runs = ", "seed = ", "[set]", "[[axis]]",
          "key = ", "values = [", "label = ", "fixed = ", "\n#--set\n", "=", "inf", "-inf", "nan",
          "+inf", "true", "false", "1e308", "4.9e-324", "-0.0", "0x7fffffffffffffff",
          "9223372036854775807", "-9223372036854775808", "1979-05-27T07:32:00Z", "'''", '"""',
          "{", "}", "[", "]", ".", ",", '"', "\\u0000", "\\U0010FFFF"]

with open(sys.argv[2], "w") as out:
    out.write("# written by tests/fuzz/make_corpus.sh (make_dict.py): the scenario and sweep "
              "targets' dictionary\n")
    for w in dict.fromkeys(words):
        out.write(entry(w) + "\n")
