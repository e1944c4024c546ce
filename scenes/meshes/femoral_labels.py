#!/usr/bin/env python3
"""Writes femoral_labels.nii.gz: a segmentation of the femoral region of
scenes/femoral.toml (seed 003 §4.3) as a scanner would give it, 1 mm voxels.

Coordinates as in that scene: x across the thigh (lateral -), y along it (+ towards the
abdomen), z up, the skin at z = 0; the block spans 140 x 120 x 60 mm. Labels:

  1 subcutaneous fat   the top 8 mm (its lower face is the fascia lata)
  2 muscle             the rest of the soft tissue
  3 iliacus            the lateral compartment under the fascia iliaca (z -13 to -40 mm)
  4 femoral artery     radius 4 mm, along y at x = 0, z = -18 mm
  5 femoral vein       radius 5 mm, along y at x = 14 mm, z = -19 mm
  6 femur              radius 10 mm, along y at x = -35 mm, z = -48 mm
  7 hip                a ball of radius 13 mm at (35, 45, -45) mm
  8 inguinal ligament  radius 3 mm, along the groin (8 degrees off x) at z = -5 mm

Python's standard library only (struct, gzip), so that anyone can re-make the image:
    python3 scenes/meshes/femoral_labels.py scenes/meshes/femoral_labels.nii.gz
"""
import gzip
import math
import struct
import sys

SIZE = (140, 120, 60)          # voxels along x, y, z
SPACING = 1.0                  # mm
ORIGIN = (-69.5, -59.5, -59.5)  # mm, the centre of voxel (0, 0, 0)


def cylinder_along_y(x, z, cx, cz, r):
    return (x - cx) ** 2 + (z - cz) ** 2 <= r * r


def label_at(x, y, z):
    # The ligament runs from the anterior superior iliac spine towards the pubis: a line
    # through (-54.46, 36.35, -5) mm turned 8 degrees about z from the x axis.
    a = math.radians(8.0)
    dx, dy, dz = x + 54.46, y - 36.35, z + 5.0
    along = dx * math.cos(a) + dy * math.sin(a)
    across = -dx * math.sin(a) + dy * math.cos(a)
    if abs(along) <= 55.0 and across * across + dz * dz <= 9.0:
        return 8
    if (x - 35.0) ** 2 + (y - 45.0) ** 2 + (z + 45.0) ** 2 <= 13.0 ** 2:
        return 7
    if cylinder_along_y(x, z, -35.0, -48.0, 10.0):
        return 6
    if cylinder_along_y(x, z, 14.0, -19.0, 5.0):
        return 5
    if cylinder_along_y(x, z, 0.0, -18.0, 4.0):
        return 4
    if -65.0 <= x <= -7.0 and -40.0 <= z <= -13.0:
        return 3
    if z >= -8.0:
        return 1
    return 2


def nifti_header(nx, ny, nz):
    h = bytearray(348)
    struct.pack_into("<i", h, 0, 348)                                   # sizeof_hdr
    struct.pack_into("<8h", h, 40, 3, nx, ny, nz, 1, 1, 1, 1)          # dim
    struct.pack_into("<h", h, 70, 2)                                    # datatype: uint8
    struct.pack_into("<h", h, 72, 8)                                    # bitpix
    struct.pack_into("<8f", h, 76, 1.0, SPACING, SPACING, SPACING, 1, 1, 1, 1)  # pixdim (qfac 1)
    struct.pack_into("<f", h, 108, 352.0)                              # vox_offset
    struct.pack_into("<f", h, 112, 1.0)                                # scl_slope
    h[123] = 2                                                          # xyzt_units: mm
    h[148:148 + 40] = b"tactus femoral phantom".ljust(40, b"\0")       # descrip
    struct.pack_into("<hh", h, 252, 1, 1)                               # qform_code, sform_code
    struct.pack_into("<6f", h, 256, 0, 0, 0, *ORIGIN)                   # quatern b c d, offsets
    struct.pack_into("<4f", h, 280, SPACING, 0, 0, ORIGIN[0])           # srow_x
    struct.pack_into("<4f", h, 296, 0, SPACING, 0, ORIGIN[1])           # srow_y
    struct.pack_into("<4f", h, 312, 0, 0, SPACING, ORIGIN[2])           # srow_z
    h[344:348] = b"n+1\0"
    return bytes(h) + b"\0\0\0\0"                                       # no extensions


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: femoral_labels.py OUT.nii.gz")
    nx, ny, nz = SIZE
    voxels = bytearray(nx * ny * nz)
    i = 0
    for k in range(nz):
        z = ORIGIN[2] + k * SPACING
        for j in range(ny):
            y = ORIGIN[1] + j * SPACING
            for n in range(nx):
                voxels[i] = label_at(ORIGIN[0] + n * SPACING, y, z)
                i += 1
    # mtime 0: the same bytes on every run.
    with open(sys.argv[1], "wb") as f:
        f.write(gzip.compress(nifti_header(nx, ny, nz) + bytes(voxels), compresslevel=9, mtime=0))


if __name__ == "__main__":
    main()
