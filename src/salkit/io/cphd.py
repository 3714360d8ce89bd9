"""CPHD 1.0.1 files (NGA.STND.0068) in and out, through sarkit.

salkit's frame is local: the scene centre is the origin, x east, y north, z up. A CPHD file is
earth-fixed (ECF, WGS-84), so writing needs a geodetic origin: the dataset attribute
``origin_llh`` (deg, deg, m) when it has one, else the ``origin`` argument (default 0 deg N,
0 deg E, 0 m; the image does not depend on it). Reading maps the file's positions back into the
local frame of its image-area reference point (IARP).

Signal model: salkit's phase history P(f) = exp(-j 2 pi f dTOA), dTOA = 2 (R - R_ref)/c, is CPHD's
FX domain with SGN = -1, one vector per pulse, the stabilisation reference point (SRP) on the line
of sight at the reference range (so |TxPos - SRPPos| = R_ref).
"""
from __future__ import annotations

import datetime as _dt
from pathlib import Path

import numpy as np
import xarray as xr
from xarray.backends import BackendArray
from xarray.core.indexing import IndexingSupport, LazilyIndexedArray, explicit_indexing_adapter

from ..constants import SPEED_OF_LIGHT
from ..errors import DataFileError
from .reading import input_file
from .writing import atomic_path
from .ingest import normalise_phase_history

NS = "http://api.nsgreg.nga.mil/schema/cphd/1.0.1"
DEFAULT_ORIGIN = (0.0, 0.0, 0.0)


def _sarkit():
    try:
        import sarkit.cphd as skcphd
        import sarkit.wgs84 as wgs84
    except ImportError as e:  # pragma: no cover - sarkit is a dependency
        raise DataFileError(f"CPHD needs the sarkit package ({e}); pip install sarkit") from None
    return skcphd, wgs84


def local_frame(origin_llh) -> tuple[np.ndarray, np.ndarray]:
    """ECF position of a geodetic origin and the rotation local (east, north, up) -> ECF.

    Parameters
    ----------
    origin_llh : (3,) array_like
        Latitude (deg), longitude (deg), height above the ellipsoid (m).

    Returns
    -------
    origin_ecf : float64 (3,)
        m.
    rot : float64 (3, 3)
        Columns are the east, north and up unit vectors in ECF.
    """
    _, wgs84 = _sarkit()
    llh = np.asarray(origin_llh, dtype=np.float64)
    rot = np.stack([wgs84.east(llh), wgs84.north(llh), wgs84.up(llh)], axis=1)
    return wgs84.geodetic_to_cartesian(llh), rot


def _f(v) -> str:
    return repr(float(v))


def _xyz(tag, v):
    return f"<{tag}><X>{_f(v[0])}</X><Y>{_f(v[1])}</Y><Z>{_f(v[2])}</Z></{tag}>"


def _pvp_xml(names):
    sizes = {"TxTime": 1, "TxPos": 3, "TxVel": 3, "RcvTime": 1, "RcvPos": 3, "RcvVel": 3, "SRPPos": 3,
             "aFDOP": 1, "aFRR1": 1, "aFRR2": 1, "FX1": 1, "FX2": 1, "TOA1": 1, "TOA2": 1,
             "TDTropoSRP": 1, "SC0": 1, "SCSS": 1}
    out, off = [], 0
    for n in names:
        fmt = "X=F8;Y=F8;Z=F8;" if sizes[n] == 3 else "F8"
        out.append(f"<{n}><Offset>{off}</Offset><Size>{sizes[n]}</Size><Format>{fmt}</Format></{n}>")
        off += sizes[n]
    return "".join(out), off * 8


PVP_NAMES = ["TxTime", "TxPos", "TxVel", "RcvTime", "RcvPos", "RcvVel", "SRPPos", "aFDOP", "aFRR1", "aFRR2",
             "FX1", "FX2", "TOA1", "TOA2", "TDTropoSRP", "SC0", "SCSS"]


def write_cphd(ph: xr.Dataset, path: str | Path, origin=None, collector: str = "salkit",
               core_name: str | None = None) -> Path:
    """Write a phase-history dataset as a CPHD 1.0.1 file (atomically).

    Parameters
    ----------
    ph : xarray.Dataset
        ``salkit_kind = "phase_history"`` (see :func:`salkit.focus.range_compress` for raw data),
        frequency increasing or decreasing.
    path : str or Path
        File to write.
    origin : (lat deg, lon deg, hae m), optional
        Geodetic position of the scene centre; default the dataset's ``origin_llh`` or
        :data:`DEFAULT_ORIGIN`.
    collector, core_name : str
        CollectionID fields.

    Returns
    -------
    Path

    Raises
    ------
    DataFileError
        A dataset that is not a phase history.
    """
    import lxml.etree as et
    skcphd, wgs84 = _sarkit()
    if ph.attrs.get("salkit_kind") != "phase_history":
        raise DataFileError(f"CPHD export needs a phase history, got salkit_kind = {ph.attrs.get('salkit_kind')!r}")
    ph = normalise_phase_history(ph)
    freq = np.asarray(ph["frequency"].values, np.float64)
    data = np.asarray(ph["signal"].values, np.complex64)
    if freq[1] < freq[0]:
        freq, data = freq[::-1].copy(), data[:, ::-1].copy()
    P, M = data.shape
    pos_l = np.asarray(ph["position"].values, np.float64)
    ref = np.asarray(ph["reference_range"].values, np.float64)
    llh = np.asarray(origin if origin is not None else ph.attrs.get("origin_llh", DEFAULT_ORIGIN), np.float64)
    o_ecf, rot = local_frame(llh)
    st = np.asarray(ph["slow_time"].values, np.float64)
    if ph.attrs.get("slow_time_units") == "pulse":  # no times in the data: a nominal 1 kHz
        st = st * 1e-3
    t = st - st[0]
    if "velocity" in ph and ph["velocity"].shape == (P, 3):
        vel_l = np.asarray(ph["velocity"].values, np.float64)
    else:
        vel_l = np.gradient(pos_l, t, axis=0)
    pos = o_ecf + pos_l @ rot.T
    vel = vel_l @ rot.T
    look = -pos_l / np.linalg.norm(pos_l, axis=1, keepdims=True)
    srp_l = pos_l + ref[:, None] * look
    srp = o_ecf + srp_l @ rot.T
    srp_fixed = bool(np.max(np.linalg.norm(srp_l, axis=1)) < 1e-6)
    if srp_fixed:
        srp[:] = o_ecf
    df = float(freq[1] - freq[0])
    fx1, fx2 = float(freq[0] - df / 2), float(freq[-1] + df / 2)
    toa_half = 0.4 / df  # TOA swath: 0.8 of the unambiguous 1/df (FX oversampling 1.25, CPHD asks >= 1.2)
    c = SPEED_OF_LIGHT
    chirp = float(ph.attrs.get("chirp_rate", 0.0) or 0.0)
    pvp_body, nbytes = _pvp_xml(PVP_NAMES)
    pvp = np.zeros(P, dtype=[(n, ">f8", (3,)) if n in ("TxPos", "TxVel", "RcvPos", "RcvVel", "SRPPos")
                             else (n, ">f8") for n in PVP_NAMES])
    rdot = np.sum(vel_l * (pos_l - srp_l) / np.linalg.norm(pos_l - srp_l, axis=1, keepdims=True), axis=1)
    pvp["TxTime"] = t
    pvp["TxPos"] = pos
    pvp["TxVel"] = vel
    pvp["RcvTime"] = t + 2 * ref / c
    pvp["RcvPos"] = pos
    pvp["RcvVel"] = vel
    pvp["SRPPos"] = srp
    pvp["aFDOP"] = -2.0 / c * rdot
    if chirp > 0:
        pvp["aFRR2"] = 2.0 / (c * chirp)
        pvp["aFRR1"] = 0.5 * (fx1 + fx2) * pvp["aFRR2"]
    pvp["FX1"], pvp["FX2"] = fx1, fx2
    pvp["TOA1"], pvp["TOA2"] = -toa_half, toa_half
    pvp["SC0"], pvp["SCSS"] = freq[0], df
    ref_i = P // 2
    # image area: the unambiguous extent on the ground, in the local frame's x, y
    half = min(0.5 * c * toa_half, 1e4)
    corners_l = np.array([[-half, -half, 0], [-half, half, 0], [half, half, 0], [half, -half, 0]])
    corners = wgs84.cartesian_to_geodetic(o_ecf + corners_l @ rot.T)
    n_grid = 1024
    t_ref = t + ref / c  # when each pulse's centre passes the SRP (CPHD signal model, monostatic)
    t_mid = 0.5 * float(t_ref[0] + t_ref[-1])
    dwell = float(t_ref[-1] - t_ref[0]) * (1 - 1e-9)  # within the vectors' reference times
    start = _dt.datetime(2000, 1, 1) + _dt.timedelta(seconds=0)
    mode = "SPOTLIGHT" if str(ph.attrs.get("mode", "spotlight")) == "spotlight" else "STRIPMAP"
    iacp = "".join(f'<IACP index="{i + 1}"><Lat>{_f(corners[i, 0])}</Lat><Lon>{_f(corners[i, 1])}</Lon></IACP>'
                   for i in range(4))
    xml = f"""<CPHD xmlns="{NS}">
<CollectionID><CollectorName>{collector}</CollectorName><CoreName>{core_name or Path(path).stem}</CoreName>
<CollectType>MONOSTATIC</CollectType><RadarMode><ModeType>{mode}</ModeType></RadarMode>
<Classification>UNCLASSIFIED</Classification><ReleaseInfo>UNRESTRICTED</ReleaseInfo></CollectionID>
<Global><DomainType>FX</DomainType><SGN>-1</SGN>
<Timeline><CollectionStart>{start.isoformat()}.000000Z</CollectionStart><TxTime1>{_f(t[0])}</TxTime1><TxTime2>{_f(t[-1])}</TxTime2></Timeline>
<FxBand><FxMin>{_f(fx1)}</FxMin><FxMax>{_f(fx2)}</FxMax></FxBand>
<TOASwath><TOAMin>{_f(-toa_half)}</TOAMin><TOAMax>{_f(toa_half)}</TOAMax></TOASwath></Global>
<SceneCoordinates><EarthModel>WGS_84</EarthModel>
<IARP>{_xyz("ECF", o_ecf)}<LLH><Lat>{_f(llh[0])}</Lat><Lon>{_f(llh[1])}</Lon><HAE>{_f(llh[2])}</HAE></LLH></IARP>
<ReferenceSurface><Planar>{_xyz("uIAX", rot[:, 0])}{_xyz("uIAY", rot[:, 1])}</Planar></ReferenceSurface>
<ImageArea><X1Y1><X>{_f(-half)}</X><Y>{_f(-half)}</Y></X1Y1><X2Y2><X>{_f(half)}</X><Y>{_f(half)}</Y></X2Y2></ImageArea>
<ImageAreaCornerPoints>{iacp}</ImageAreaCornerPoints>
<ImageGrid><IARPLocation><Line>{_f(n_grid / 2 - 0.5)}</Line><Sample>{_f(n_grid / 2 - 0.5)}</Sample></IARPLocation>
<IAXExtent><LineSpacing>{_f(2 * half / n_grid)}</LineSpacing><FirstLine>0</FirstLine><NumLines>{n_grid}</NumLines></IAXExtent>
<IAYExtent><SampleSpacing>{_f(2 * half / n_grid)}</SampleSpacing><FirstSample>0</FirstSample><NumSamples>{n_grid}</NumSamples></IAYExtent>
</ImageGrid></SceneCoordinates>
<Data><SignalArrayFormat>CF8</SignalArrayFormat><NumBytesPVP>{nbytes}</NumBytesPVP><NumCPHDChannels>1</NumCPHDChannels>
<Channel><Identifier>1</Identifier><NumVectors>{P}</NumVectors><NumSamples>{M}</NumSamples>
<SignalArrayByteOffset>0</SignalArrayByteOffset><PVPArrayByteOffset>0</PVPArrayByteOffset></Channel>
<NumSupportArrays>0</NumSupportArrays></Data>
<Channel><RefChId>1</RefChId><FXFixedCPHD>true</FXFixedCPHD><TOAFixedCPHD>true</TOAFixedCPHD>
<SRPFixedCPHD>{str(srp_fixed).lower()}</SRPFixedCPHD>
<Parameters><Identifier>1</Identifier><RefVectorIndex>{ref_i}</RefVectorIndex><FXFixed>true</FXFixed>
<TOAFixed>true</TOAFixed><SRPFixed>{str(srp_fixed).lower()}</SRPFixed>
<Polarization><TxPol>UNSPECIFIED</TxPol><RcvPol>UNSPECIFIED</RcvPol></Polarization>
<FxC>{_f(0.5 * (fx1 + fx2))}</FxC><FxBW>{_f(fx2 - fx1)}</FxBW><TOASaved>{_f(2 * toa_half)}</TOASaved>
<DwellTimes><CODId>COD</CODId><DwellId>DWELL</DwellId></DwellTimes></Parameters></Channel>
<PVP>{pvp_body}</PVP>
<Dwell><NumCODTimes>1</NumCODTimes><CODTime><Identifier>COD</Identifier>
<CODTimePoly order1="0" order2="0"><Coef exponent1="0" exponent2="0">{_f(t_mid)}</Coef></CODTimePoly></CODTime>
<NumDwellTimes>1</NumDwellTimes><DwellTime><Identifier>DWELL</Identifier>
<DwellTimePoly order1="0" order2="0"><Coef exponent1="0" exponent2="0">{_f(dwell)}</Coef></DwellTimePoly></DwellTime></Dwell>
<ReferenceGeometry/>
</CPHD>"""
    root = et.fromstring(xml.encode())
    tree = et.ElementTree(root)
    newgeo = skcphd.compute_reference_geometry(tree, pvp)
    old = root.find(f"{{{NS}}}ReferenceGeometry")
    root.replace(old, newgeo)
    meta = skcphd.Metadata(xmltree=tree, file_header_part=skcphd.FileHeaderPart(
        additional_kvps={"SALKIT_VERSION": str(ph.attrs.get("salkit_version", ""))}))
    with atomic_path(path) as tmp:
        with open(tmp, "wb") as fh, skcphd.Writer(fh, meta) as w:
            w.write_signal("1", np.ascontiguousarray(data))
            w.write_pvp("1", pvp)
    return Path(path)


class CPHDSignal(BackendArray):
    """A CPHD channel's signal (vectors x samples) read through sarkit only where indexed: each read
    opens the file and takes the vectors it needs (``read_signal(start_vector=, stop_vector=)``),
    conjugated to salkit's sign when the file's SGN is +1, as complex64.

    Parameters
    ----------
    path : Path
    channel : str
    shape : (int, int)
    sgn : int
    """

    def __init__(self, path: Path, channel: str, shape, sgn: int):
        self.path, self.channel, self.shape, self.sgn = Path(path), channel, tuple(shape), int(sgn)
        self.dtype = np.dtype(np.complex64)

    def __getitem__(self, key):
        return explicit_indexing_adapter(key, self.shape, IndexingSupport.BASIC, self._raw)

    def _raw(self, key):
        rows, cols = (tuple(key) + (slice(None),) * 2)[:2]
        r = range(self.shape[0])[rows] if isinstance(rows, slice) else range(int(rows), int(rows) + 1)
        if len(r) == 0:
            return np.zeros((0, self.shape[1]), np.complex64)[:, cols]
        a, b = r.start, r.stop if r.step > 0 else r.start + 1
        skcphd, _ = _sarkit()
        try:
            with open(self.path, "rb") as fh, skcphd.Reader(fh) as rd:
                data = rd.read_signal(self.channel, start_vector=min(a, b), stop_vector=max(a, b))
        except Exception as e:  # noqa: BLE001 - sarkit and numpy raise many kinds for bad files
            raise DataFileError(f"{self.path}: vectors {a} to {b - 1} cannot be read: {type(e).__name__}: {e}") from None
        sig = np.asarray(data, np.complex64)
        if self.sgn == 1:
            sig = np.conj(sig)
        sig = sig[::r.step] if r.step != 1 else sig
        return sig[0, cols] if not isinstance(rows, slice) else sig[:, cols]


def read_cphd(path: str | Path, channel: str | None = None, lazy: bool = False) -> xr.Dataset:
    """Read one channel of a CPHD file (FX domain) as a salkit phase-history dataset.

    Parameters
    ----------
    path : str or Path
    channel : str, optional
        Channel identifier; default the reference channel.
    lazy : bool
        Read the metadata and the per-vector parameters now and the signal only where it is
        indexed (:class:`CPHDSignal`: a block of vectors at a time through sarkit), for a
        collection larger than memory.

    Returns
    -------
    xarray.Dataset
        ``salkit_kind = "phase_history"`` in the local frame of the file's IARP (x east, y north,
        z up), ``origin_llh`` recording that point; a file with SGN = +1 is conjugated.

    Raises
    ------
    DataFileError
        Not a CPHD file, TOA domain, bistatic geometry or a varying frequency sampling.
    """
    skcphd, wgs84 = _sarkit()
    p = input_file(path)
    try:
        with open(p, "rb") as fh, skcphd.Reader(fh) as r:
            tree = r.metadata.xmltree
            ch = channel or tree.findtext("{*}Channel/{*}RefChId")
            if lazy:  # the vectors' parameters now, the signal where indexed
                pvp = r.read_pvps(ch)
                nv = int(tree.findtext(f"{{*}}Data/{{*}}Channel[{{*}}Identifier='{ch}']/{{*}}NumVectors"))
                ns = int(tree.findtext(f"{{*}}Data/{{*}}Channel[{{*}}Identifier='{ch}']/{{*}}NumSamples"))
                data = None
            else:
                data, pvp = r.read_channel(ch)
    except DataFileError:
        raise
    except Exception as e:  # noqa: BLE001 - sarkit and lxml raise many kinds for bad files
        raise DataFileError(f"{p}: cannot be read as CPHD: {type(e).__name__}: {e}") from None
    dom = tree.findtext("{*}Global/{*}DomainType")
    if dom != "FX":
        raise DataFileError(f"{p}: Global/DomainType = {dom!r}; salkit reads FX-domain CPHD only")
    sgn = int(tree.findtext("{*}Global/{*}SGN"))
    sc0, scss = np.asarray(pvp["SC0"], np.float64), np.asarray(pvp["SCSS"], np.float64)
    if np.ptp(sc0) > 1e-6 * abs(scss[0]) or np.ptp(scss) > 1e-9 * abs(scss[0]):
        raise DataFileError(f"{p}: SC0/SCSS vary between vectors (SC0 spread {np.ptp(sc0):.6g} Hz, SCSS "
                            f"spread {np.ptp(scss):.6g} Hz); salkit needs one frequency sampling")
    if np.max(np.abs(pvp["TxPos"] - pvp["RcvPos"])) > 1.0:
        raise DataFileError(f"{p}: transmit and receive positions differ by up to "
                            f"{np.max(np.abs(pvp['TxPos'] - pvp['RcvPos'])):.3g} m; salkit is monostatic")
    llh = np.array([float(tree.findtext("{*}SceneCoordinates/{*}IARP/{*}LLH/{*}" + k)) for k in ("Lat", "Lon", "HAE")])
    o_ecf, rot = local_frame(llh)
    pos = (np.asarray(pvp["TxPos"], np.float64) - o_ecf) @ rot
    vel = np.asarray(pvp["TxVel"], np.float64) @ rot
    ref = np.linalg.norm(np.asarray(pvp["TxPos"], np.float64) - np.asarray(pvp["SRPPos"], np.float64), axis=1)
    if data is None:
        sig = xr.Variable(("slow_time", "frequency"), LazilyIndexedArray(CPHDSignal(p, ch, (nv, ns), sgn)))
        M = ns
    else:
        M = data.shape[1]
        sig = np.asarray(data, np.complex64)
        if sgn == 1:
            sig = np.conj(sig)
    freq = sc0[0] + scss[0] * np.arange(M)
    mode = tree.findtext("{*}CollectionID/{*}RadarMode/{*}ModeType") or "SPOTLIGHT"
    attrs = {"salkit_kind": "phase_history", "salkit_format": "1.0", "origin_llh": llh,
             "mode": "stripmap" if mode.upper() == "STRIPMAP" else "spotlight", "source_format": "CPHD 1.0",
             "source_file": p.name, "cphd_sgn": sgn}
    if np.all(np.asarray(pvp["aFRR2"]) > 0):
        attrs["chirp_rate"] = float(2.0 / (SPEED_OF_LIGHT * np.median(pvp["aFRR2"])))
    ds = xr.Dataset(
        {"signal": sig if data is None else (("slow_time", "frequency"), sig),
         "position": (("slow_time", "xyz"), pos),
         "velocity": (("slow_time", "xyz"), vel),
         "reference_range": (("slow_time",), ref)},
        coords={"slow_time": ("slow_time", np.asarray(pvp["TxTime"], np.float64), {"units": "s"}),
                "frequency": ("frequency", freq, {"units": "Hz"}), "xyz": ("xyz", ["x", "y", "z"])},
        attrs=attrs)
    ds.encoding["source"] = str(p)
    return ds


def failures_by_severity(con) -> dict:
    """Failed checks of a sarkit consistency checker, split into ``errors`` and ``warnings``
    (lists of "check: requirement" lines).

    Parameters
    ----------
    con : sarkit consistency checker
        After ``check()``.

    Returns
    -------
    dict
        ``errors``, ``warnings``: lists of str.
    """
    out = {"errors": [], "warnings": []}
    for name, f in con.failures().items():
        for d in f.get("details", []):
            if not d.get("passed", True):
                key = "errors" if d.get("severity") == "Error" else "warnings"
                out[key].append(f"{name}: {d.get('details', '')}")
    return out


def run_checker(checker_cls, path: str | Path, **kw) -> dict:
    """Run a sarkit consistency checker class (``CphdConsistency``, ``SicdConsistency``) on a file.

    Parameters
    ----------
    checker_cls : type
        ``sarkit.verification.CphdConsistency`` or ``SicdConsistency``.
    path : path
    **kw
        Passed to the checker.

    Returns
    -------
    dict
        :func:`failures_by_severity` of the result.
    """
    with open(input_file(path), "rb") as fh:
        con = checker_cls.from_file(fh, **kw)
        con.check()
    return failures_by_severity(con)


def check_cphd(path: str | Path) -> dict:
    """Run sarkit's CPHD consistency checker (schema included, thorough).

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    dict
        ``errors`` and ``warnings``: lists of "check: requirement" lines (empty when consistent).
    """
    from sarkit.verification import CphdConsistency
    return run_checker(CphdConsistency, path, thorough=True)


__all__ = ["DEFAULT_ORIGIN", "check_cphd", "failures_by_severity", "local_frame", "read_cphd", "write_cphd"]
