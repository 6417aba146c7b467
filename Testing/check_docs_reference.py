"""docs/reference.md names every public name of the Python package and every property of the
plugin's proxies, so that what a user can call or set is documented.

    check_docs_reference.py REPO              check; one FAIL line per missing name, exit 1
    check_docs_reference.py REPO --rows PROXY print the reference table of PROXY's
                                              properties from its XML (to paste)

Public names: those the package's __init__.py imports from its modules (multichannel_explorer
is imported as text, not run: it needs ParaView). Properties: every *Property element of
the SourceProxy / RepresentationProxy / WriterProxy elements of
Plugin/MultichannelExplorer/*.xml outside the internal_sources group and the base proxies
of the mcv_feature_settings group (their properties count in the proxies that inherit
them through base_proxygroup / base_proxyname). A name counts as
documented when it appears in backquotes (`name` or `name(...)`) in docs/reference.md."""
import ast
import glob
import os
import re
import sys
import xml.etree.ElementTree as ET

PROXY_TAGS = ("SourceProxy", "RepresentationProxy", "WriterProxy")


def public_names(repo):
    init = os.path.join(repo, "Plugin/MultichannelExplorer/multichannel_explorer/__init__.py")
    names = []
    for node in ast.parse(open(init).read()).body:
        if isinstance(node, ast.ImportFrom) and node.module:
            names += [a.asname or a.name for a in node.names if not a.name.startswith("_")]
    return names


def flattened(proxy, every):
    """The proxy with the properties of its base proxy (base_proxygroup / base_proxyname)
    first, as ParaView merges them; a property marked override replaces the base's."""
    base = every.get((proxy.get("base_proxygroup"), proxy.get("base_proxyname")))
    if base is None:
        return proxy
    merged = ET.Element(proxy.tag, proxy.attrib)
    own = {c.get("name"): c for c in proxy if c.tag.endswith("Property") and c.get("override")}
    for child in flattened(base, every):
        if child.tag == "Documentation":
            continue
        merged.append(own.pop(child.get("name"), child) if child.tag.endswith("Property") else child)
    for child in proxy:
        if not (child.tag.endswith("Property") and child.get("override")):
            merged.append(child)
    return merged


def proxies(repo):
    """(proxy name, xml element with its inherited properties) of every user-visible proxy."""
    every, shown = {}, []
    for path in sorted(glob.glob(os.path.join(repo, "Plugin/MultichannelExplorer/*.xml"))):
        for group in ET.parse(path).getroot().findall("ProxyGroup"):
            for proxy in group:
                if proxy.tag in PROXY_TAGS:
                    every[(group.get("name"), proxy.get("name"))] = proxy
                    if group.get("name") not in ("internal_sources", "mcv_feature_settings"):
                        shown.append(proxy)
    for proxy in shown:
        yield proxy.get("name"), flattened(proxy, every)


def first_sentence(element):
    doc = element.find("Documentation")
    text = " ".join((doc.text or "").split()) if doc is not None else ""
    m = re.match(r"(.+?\.)(\s+[A-Z]|$)", text)
    return m.group(1) if m else text


def rows(proxy):
    """The reference's table rows of one proxy: group, property, default, first sentence of
    its documentation and its choices; settable properties first, read-only ones last."""
    groups = {}
    for group in proxy.iter("PropertyGroup"):
        for prop in group.findall("Property"):
            groups[prop.get("name")] = group.get("label")
    out = []
    for prop in proxy:
        if not prop.tag.endswith("Property"):
            continue
        default = prop.get("default_values", "")
        default = default[8:] if default.startswith("0;0;0;0;") else default
        default = "" if default == "none" else default
        choices = ""
        enum = prop.find("EnumerationDomain")
        if enum is not None:
            entries = enum.findall("Entry")
            default = next((e.get("text") for e in entries if e.get("value") == default), default)
            choices = " Choices: " + ", ".join(e.get("text") for e in entries) + "."
        info = prop.get("information_only") == "1"
        out.append((info, "| %s | `%s`%s | %s | %s |" % (
            groups.get(prop.get("name"), ""), prop.get("name"), " (read-only)" if info else "",
            default, (first_sentence(prop) + choices).replace("|", "\\|"))))
    return ["| group | property | default | what |", "| --- | --- | --- | --- |"] + [
        r for _, r in sorted(out, key=lambda r: r[0])]


def main(argv):
    if len(argv) < 2:
        print(__doc__)
        return 2
    repo = argv[1]
    if len(argv) == 4 and argv[2] == "--rows":
        for name, proxy in proxies(repo):
            if name == argv[3]:
                print(first_sentence(proxy) + "\n")
                print("\n".join(rows(proxy)))
                return 0
        print("no proxy %s" % argv[3])
        return 1
    text = open(os.path.join(repo, "docs", "reference.md"), encoding="utf-8").read()
    quoted = set(re.findall(r"`([A-Za-z_][A-Za-z0-9_]*)", text))
    missing = ["the Python helper %s" % n for n in public_names(repo) if n not in quoted]
    count = len(public_names(repo))
    for name, proxy in proxies(repo):
        if name not in text:
            missing.append("the proxy %s (check_docs_reference.py REPO --rows %s)" % (name, name))
        for prop in proxy:
            if prop.tag.endswith("Property"):
                count += 1
                if prop.get("name") not in quoted:
                    missing.append("%s's property %s" % (name, prop.get("name")))
    for m in missing:
        print("FAIL: docs/reference.md does not name " + m)
    print("%d names, %d missing from docs/reference.md" % (count, len(missing)))
    return 1 if missing else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
