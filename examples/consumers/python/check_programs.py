#!/usr/bin/env python3
"""Checks the part programs named on the command line with the osplint C
library (through ctypes), each with the nearest osplint.toml of its
directory, and prints the findings as PATH:LINE:COLUMN: SEVERITY: MESSAGE [RULE].
Exit code: 0 no findings, 1 findings, 2 a file or configuration error.

The library is OSPLINT_LIBRARY (a path to libosplint.so) when set, else the
one the system's loader finds.
"""
import ctypes
import ctypes.util
import os
import sys

OK = 0


class Diagnostic(ctypes.Structure):
    # osplint_diagnostic of osplint/osplint_c.h, field for field.
    _fields_ = [
        ("rule", ctypes.c_char_p),
        ("name", ctypes.c_char_p),
        ("severity", ctypes.c_int),
        ("message", ctypes.c_char_p),
        ("line", ctypes.c_uint),
        ("column", ctypes.c_uint),
        ("end_line", ctypes.c_uint),
        ("end_column", ctypes.c_uint),
        ("byte_begin", ctypes.c_size_t),
        ("byte_end", ctypes.c_size_t),
        ("line_text", ctypes.c_char_p),
        ("fix_title", ctypes.c_char_p),
        ("note_count", ctypes.c_size_t),
    ]


def load_library():
    path = os.environ.get("OSPLINT_LIBRARY") or ctypes.util.find_library("osplint")
    if not path:
        raise OSError("libosplint not found (set OSPLINT_LIBRARY)")
    lib = ctypes.CDLL(path)
    handle = ctypes.c_void_p
    out = ctypes.POINTER(ctypes.c_void_p)
    err = ctypes.POINTER(ctypes.c_void_p)  # char** kept as a raw pointer, released by osplint_string_free
    signatures = {
        "osplint_version": (ctypes.c_char_p, []),
        "osplint_severity_name": (ctypes.c_char_p, [ctypes.c_int]),
        "osplint_string_free": (None, [ctypes.c_void_p]),
        "osplint_config_new": (ctypes.c_int, [out, err]),
        "osplint_config_load": (ctypes.c_int, [ctypes.c_char_p, out, err]),
        "osplint_config_find": (ctypes.c_int, [ctypes.c_char_p, out, err]),
        "osplint_config_free": (None, [handle]),
        "osplint_check_file": (ctypes.c_int, [ctypes.c_char_p, handle, handle, out, err]),
        "osplint_result_count": (ctypes.c_size_t, [handle]),
        "osplint_result_diagnostic": (ctypes.POINTER(Diagnostic), [handle, ctypes.c_size_t]),
        "osplint_result_free": (None, [handle]),
    }
    for name, (restype, argtypes) in signatures.items():
        f = getattr(lib, name)
        f.restype = restype
        f.argtypes = argtypes
    return lib


class OsplintError(Exception):
    pass


class Osplint:
    def __init__(self):
        self.lib = load_library()

    def _take_string(self, ptr):
        """The text of a string osplint returned, which is then released."""
        if not ptr.value:
            return None
        text = ctypes.string_at(ptr.value).decode("utf-8", "replace")
        self.lib.osplint_string_free(ptr)
        return text

    def _call(self, name, *args):
        error = ctypes.c_void_p()
        status = getattr(self.lib, name)(*args, ctypes.byref(error))
        message = self._take_string(error)
        if status != OK:
            raise OsplintError(message or f"{name} failed with status {status}")

    def check(self, path):
        """The findings of one file, as (line, column, severity, message, rule) tuples."""
        directory = os.path.dirname(path) or "."
        toml = ctypes.c_void_p()
        self._call("osplint_config_find", directory.encode(), ctypes.byref(toml))
        toml_path = self._take_string(toml)
        config = ctypes.c_void_p()
        if toml_path:
            self._call("osplint_config_load", toml_path.encode(), ctypes.byref(config))
        else:
            self._call("osplint_config_new", ctypes.byref(config))
        result = ctypes.c_void_p()
        try:
            self._call("osplint_check_file", path.encode(), config, None, ctypes.byref(result))
            findings = []
            for i in range(self.lib.osplint_result_count(result)):
                d = self.lib.osplint_result_diagnostic(result, i).contents
                severity = self.lib.osplint_severity_name(d.severity).decode()
                findings.append((d.line, d.column, severity, d.message.decode("utf-8", "replace"), d.rule.decode()))
            return findings
        finally:
            self.lib.osplint_result_free(result)
            self.lib.osplint_config_free(config)


def main(argv):
    if len(argv) < 2:
        print("usage: check_programs.py FILE...", file=sys.stderr)
        return 2
    osplint = Osplint()
    status = 0
    for path in argv[1:]:
        try:
            findings = osplint.check(path)
        except OsplintError as e:
            print(e, file=sys.stderr)
            status = 2
            continue
        for line, column, severity, message, rule in findings:
            print(f"{path}:{line}:{column}: {severity}: {message} [{rule}]")
            status = max(status, 1)
    return status


if __name__ == "__main__":
    sys.exit(main(sys.argv))
