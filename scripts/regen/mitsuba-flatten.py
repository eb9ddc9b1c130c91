#!/usr/bin/env python3
"""Write a Mitsuba scene XML file with its <include>s spliced in (recursively), for
../shared/tools/mitsuba_xml.py, which looks for the <sensor> in the top file only. File names
in the fragments stay as they are: keep the output beside the input.

    python3 scripts/regen/mitsuba-flatten.py scene.xml scene-flat.xml
"""
import os, sys
import xml.etree.ElementTree as ET


def children(path):
    out = []
    for child in ET.parse(path).getroot():
        if child.tag == "include":
            out += children(os.path.join(os.path.dirname(path), child.get("filename")))
        else:
            out.append(child)
    return out


root = ET.parse(sys.argv[1]).getroot()
kids = children(sys.argv[1])
for child in list(root):
    root.remove(child)
root.extend(kids)
ET.ElementTree(root).write(sys.argv[2])
