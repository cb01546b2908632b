#!/usr/bin/env python3
"""Writes the hostile inputs of hostile.sh into a folder.

Every input is derived from the shipped rig and camera (data/) or from a
short synthetic recording (`ripple synth`), then broken in one way: nesting
far deeper than any rig, sizes no renderer can hold, ids beyond the tag
family, headers that claim more than the file holds, cut or corrupted
videos. Usage: make_inputs.py SOURCE_DIR RECORDING_DIR OUT_DIR
"""
import os
import random
import struct
import sys
import zlib

src, rec, out = sys.argv[1:4]
rig_text = open(os.path.join(src, "data/rig/default.yml")).read()
cam_text = open(os.path.join(src, "data/camera/default_640x480.yml")).read()
os.makedirs(out, exist_ok=True)
rnd = random.Random(1)


def write(name, data):
    path = os.path.join(out, name)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    mode = "wb" if isinstance(data, bytes) else "w"
    with open(path, mode) as f:
        f.write(data)


def png(w, h, pixels=None):
    """A PNG whose IHDR says w x h (valid CRCs); pixels: raw gray rows."""
    def chunk(kind, body):
        return (struct.pack(">I", len(body)) + kind + body +
                struct.pack(">I", zlib.crc32(kind + body) & 0xffffffff))
    ihdr = struct.pack(">IIBBBBB", w, h, 8, 0, 0, 0, 0)
    if pixels is None:
        pixels = b"".join(b"\0" + b"\x80" * w for _ in range(min(h, 2)))
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) +
            chunk(b"IDAT", zlib.compress(pixels)) + chunk(b"IEND", b""))


# --- rig files -------------------------------------------------------------
deep = 100000
write("rig/deep_map.yml", "%YAML:1.0\nrig_version: 1\nx: " + "{a: " * deep +
      "1" + "}" * deep + "\n")
write("rig/deep_seq.yml", "%YAML:1.0\nrig_version: 1\nx: " + "[" * deep +
      "]" * deep + "\n")
write("rig/deep_block.yml", "%YAML:1.0\nrig_version: 1\nx:\n" + "".join(
    " " * i + "- \n" for i in range(0, 1000)))
write("rig/empty_key.yml", "%YAML:1.0\na: { :1 }\n")
write("rig/empty.yml", "")
write("rig/binary.yml", bytes(rnd.getrandbits(8) for _ in range(4096)))
write("rig/nul.yml", rig_text.replace("tag36h11", "tag36h11\0\0\0"))
write("rig/huge_file.yml", rig_text + "#" + "x" * (20 << 20) + "\n")
write("rig/long_line.yml", rig_text + "junk: " + "7" * (4 << 20) + "\n")
write("rig/many_tags.yml", rig_text.replace(
    "   tags:\n", "   tags:\n" + "".join(
        "      - { id: %d, edge: 0.001, position: [ 0, 0, 0 ], "
        "quaternion: [ 1, 0, 0, 0 ] }\n" % (100 + i) for i in range(200000)),
    1))
write("rig/alias_bomb.yml", "%YAML:1.0\n" + "a0: &a0 [x, x, x, x, x, x, x, x]\n" +
      "".join("a%d: &a%d [*a%d, *a%d, *a%d, *a%d, *a%d, *a%d, *a%d, *a%d]\n" %
              ((i, i) + (i - 1,) * 8) for i in range(1, 12)) + rig_text[10:])
write("rig/board_id_beyond.yml", rig_text.replace("{ id: 3,", "{ id: 100000,"))
write("rig/pen_id_beyond.yml", rig_text.replace("{ id: 12,", "{ id: 100000,"))
write("rig/huge_inner_size.yml", rig_text.replace(
    "inner_size: [ 0.17, 0.11 ]", "inner_size: [ 1e6, 1e6 ]"))
write("rig/tiny_inner_size.yml", rig_text.replace(
    "inner_size: [ 0.17, 0.11 ]", "inner_size: [ 1e-9, 1e-9 ]"))
write("rig/inf_level.yml", rig_text.replace("water_level: 0.025",
                                            "water_level: .inf"))
write("rig/huge_edge.yml", rig_text.replace("{ id: 0, edge: 0.03,",
                                            "{ id: 0, edge: 1e30,"))
write("rig/string_version.yml", rig_text.replace("rig_version: 1",
                                                 "rig_version: \"1\""))
write("rig/dup_key.yml", rig_text.replace("rig_version: 1",
                                          "rig_version: 1\nrig_version: 1"))
write("rig/tab_indent.yml", rig_text.replace("   wall_height", "\twall_height"))
write("rig/not_utf8.yml", rig_text.replace("tag36h11", "tag36h\xff11")
      .encode("latin-1"))
write("rig/cut.yml", rig_text[:len(rig_text) // 2])

# --- voxel obstacles (rig + voxel file) ------------------------------------
vox_rig = rig_text.split("obstacles:")[0] + (
    "obstacles:\n   - { shape: voxels, frame: tank, file: %s, voxel_size: "
    "0.002, position: [ 0, 0, 0 ], quaternion: [ 1, 0, 0, 0 ] }\n")
for name in ["vox_garbage", "vox_claims_huge", "vox_cut", "vox_sparse_zero"]:
    write("rig/%s.yml" % name, vox_rig.replace("%s", name + ".vox"))
write("rig/vox_garbage.vox", bytes(rnd.getrandbits(8) for _ in range(1 << 16)))
write("rig/vox_claims_huge.vox", "ripple-voxels 1\n4096 4096 4096\n0101\n")
write("rig/vox_cut.vox", "ripple-voxels 1\n4 4 4\n" + "01" * 10 + "\n")
# A 1.5 GB file of zeros (sparse: no disk used) with no header at all.
with open(os.path.join(out, "rig/vox_sparse_zero.vox"), "wb") as f:
    f.truncate(1500 << 20)

# --- camera files ----------------------------------------------------------
def cam(old, new):
    return cam_text.replace(old, new)


write("cam/huge.yml", cam("image_width: 640\nimage_height: 480",
                          "image_width: 100000\nimage_height: 75000"))
write("cam/big.yml", cam("image_width: 640\nimage_height: 480",
                         "image_width: 20000\nimage_height: 15000"))
write("cam/inf_width.yml", cam("image_width: 640", "image_width: .inf"))
write("cam/nan_fx.yml", cam("554.25625842204079, 0., 319.5",
                            ".nan, 0., 319.5"))
write("cam/matrix_claims_huge.yml", cam("   rows: 3\n   cols: 3",
                                        "   rows: 100000\n   cols: 100000"))
write("cam/matrix_bad_dt.yml", cam("dt: d\n   data: [ 554", "dt: zz\n   data: [ 554"))
write("cam/deep.yml", "%YAML:1.0\nimage_width: " + "[" * deep + "]" * deep)
write("cam/empty.yml", "")
write("cam/binary.yml", bytes(rnd.getrandbits(8) for _ in range(4096)))
write("cam/dist_100.yml", cam("cols: 5\n   dt: d\n   data: [ 0., 0., 0., 0., 0. ]",
                              "cols: 100\n   dt: d\n   data: [ " +
                              ", ".join(["0."] * 100) + " ]"))
write("cam/tiny.yml", cam("image_width: 640\nimage_height: 480",
                          "image_width: 1\nimage_height: 1"))

# --- image folders -----------------------------------------------------------
write("img_1x1/000.png", png(1, 1))
write("img_4x3/000.png", png(4, 3))
write("img_huge_header/000.png", png(60000, 60000))
write("img_text/000.png", "this is not an image\n")
write("img_zero/000.png", b"")
good_png = open(os.path.join(rec, "frames/000000.png"), "rb").read()
write("img_cut/000.png", good_png[:len(good_png) // 2])
for d in ["ts_extra", "ts_garbage", "ts_short", "ts_nan", "ts_huge_line"]:
    for i in range(3):
        write("%s/%06d.png" % (d, i),
              open(os.path.join(rec, "frames/%06d.png" % i), "rb").read())
write("ts_extra/timestamps.csv", "frame,time_s\n0,0.0,7\n1,0.1,7\n2,0.2,7\n")
write("ts_garbage/timestamps.csv", "frame,time_s\n0,zero\n1,one\n2,two\n")
write("ts_short/timestamps.csv", "frame,time_s\n0,0.0\n")
write("ts_nan/timestamps.csv", "frame,time_s\n0,0.0\n1,nan\n2,0.2\n")
write("ts_huge_line/timestamps.csv", "frame,time_s\n0," + "9" * (8 << 20) + "\n")

# --- videos ------------------------------------------------------------------
mkv = open(os.path.join(rec, "v.mkv"), "rb").read()
write("vid/zero.mp4", b"")
write("vid/text.mp4", "this is not a video\n" * 50)
write("vid/cut95.mkv", mkv[:len(mkv) * 95 // 100])
write("vid/cut50.mkv", mkv[:len(mkv) // 2])
mid = bytearray(mkv)
for i in range(len(mid) // 2, len(mid) // 2 + 4096):
    mid[i] = rnd.getrandbits(8)
write("vid/corrupt_mid.mkv", bytes(mid))
write("vid/header_only.mkv", mkv[:4096])
