#!/usr/bin/env python3
"""Writes the text-form seeds of the `part` fuzz target (fuzz/part_file.cpp) from the real parts
in fuzz/corpus/part/*.exr, with OpenImageIO's oiiotool (openimageio-tools). The parts themselves
come from the candela program:
    candela render fuzz/scenes/part.xml --spp 4 --seed 3 --aov variance,samples --samples 0:2 -o fuzz/corpus/part/range.exr
    ... --crop 2,1,4,5 -o crop.exr;  ... --samples 1:4 --crop 0,0,8,3 -o range_crop.exr
Usage: fuzz/make_part_seeds.py   (from the repository root)"""
import glob
import re
import struct
import subprocess

for exr in sorted(glob.glob("fuzz/corpus/part/*.exr")):
    info = subprocess.run(["oiiotool", "--info", "-v", "--dumpdata", exr], capture_output=True, text=True, check=True).stdout
    size = re.search(r":\s+(\d+) x\s+(\d+),", info)
    channels = re.search(r"channel list: (.*)", info).group(1).split(", ")
    metadata = re.findall(r'^\s+(candela\.[\w.]+): "(.*)"$', info, re.M)
    values = [float(v) for line in re.findall(r"Pixel \(\d+, \d+\): (.*)", info) for v in line.split()]
    head = f"size {size.group(1)} {size.group(2)}\nchannels {','.join(channels)}\n"
    head += "".join(f"{k}={v}\n" for k, v in metadata)
    with open(exr[:-4] + ".txt", "wb") as out:
        out.write(head.encode() + b"values\n" + struct.pack(f"<{len(values)}f", *values))
