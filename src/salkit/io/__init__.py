"""NetCDF4/HDF5 reading and writing of salkit datasets (atomic writes, validated reads), and the
outside formats (CPHD, SICD, GOTCHA .mat) converted to and from them.

Modules: :mod:`~salkit.io.datasets` (salkit datasets, atomic writes), :mod:`~salkit.io.formats`
(``read_phase_data`` by suffix), :mod:`~salkit.io.ingest` (normalising outside phase histories),
:mod:`~salkit.io.cphd`, :mod:`~salkit.io.sicd`, :mod:`~salkit.io.gotcha`, :mod:`~salkit.io.screens`,
:mod:`~salkit.io.runfolder` (run folders complete or absent), :mod:`~salkit.io.meshes` (scene objects'
mesh files).
"""
from .cphd import check_cphd, read_cphd, write_cphd
from .datasets import make_image_dataset, make_raw_dataset
from .reading import describe, input_file, open_dataset, read_image, read_raw
from .writing import ChunkedFileWriter, ImageFileWriter, write_dataset, write_json_atomic, write_text_atomic
from .formats import PHASE_SUFFIXES, read_phase_data
from .gotcha import read_gotcha, write_gotcha
from .ingest import normalise_phase_history, regularise_axis
from .meshes import mesh_bounds, read_mesh_parts
from .sicd import check_sicd, read_sicd, write_sicd

__all__ = ["ChunkedFileWriter", "ImageFileWriter", "PHASE_SUFFIXES", "check_cphd", "check_sicd", "describe", "input_file", "make_image_dataset",
           "make_raw_dataset", "mesh_bounds", "normalise_phase_history", "open_dataset", "read_cphd", "read_gotcha", "read_image",
           "read_mesh_parts", "read_phase_data", "read_raw", "read_sicd", "regularise_axis", "write_cphd", "write_dataset",
           "write_gotcha", "write_json_atomic", "write_sicd", "write_text_atomic"]
