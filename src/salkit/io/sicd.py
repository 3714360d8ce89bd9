"""SICD 1.3.0 export of salkit images (NGA.STND.0024, NITF container), through sarkit.

The image plane, its axes and spacings, the resolutions and the window come from the image's
attributes; the collection (antenna positions and times) from its ``collection_position`` and
``collection_time`` variables, which :func:`salkit.focus.focus` writes. The local scene frame
(x east, y north, z up, scene centre at the origin) is placed on the earth at ``origin_llh``
(default 0 deg N, 0 deg E, 0 m, as for CPHD).

SICD's rows run along range (the image's ``range`` axis), its columns along azimuth: the pixel
array is the transpose of salkit's (azimuth, range). Grid type ``PLANE`` with
``ImageFormAlgo = OTHER`` describes every salkit image former (backprojection, PFA resampled to
the plane grid, omega-k).
"""
from __future__ import annotations

import datetime as _dt
from pathlib import Path

import numpy as np
import xarray as xr

from ..constants import SPEED_OF_LIGHT
from ..errors import DataFileError
from .reading import input_file
from .cphd import DEFAULT_ORIGIN, _f, _xyz, local_frame, run_checker
from .writing import atomic_path

NS = "urn:SICD:1.3.0"
WINDOWS = {"none": "UNIFORM", "hamming": "HAMMING", "taylor": "TAYLOR"}


def _rect_irw(attrs, axis: str, bandwidth: float) -> float:
    """SICD's ImpRespWid along an axis: the weighted rectangle's of ImpRespBW (SICD's grid model,
    which sarkit checks), the window's IRW factor over the bandwidth; the image's own IRW theory
    where it has no factor (before 0.27), which is that rectangle's too."""
    if "window_irw_factor" in attrs:
        return float(attrs["window_irw_factor"]) / bandwidth
    return float(attrs.get(f"irw_{axis}_theory", 0.886 / bandwidth))


def _poly1(tag, coefs):
    n = len(coefs) - 1
    return (f'<{tag} order1="{n}">' + "".join(f'<Coef exponent1="{i}">{_f(c)}</Coef>' for i, c in enumerate(coefs))
            + f"</{tag}>")


def _xyzpoly(tag, coefs):
    """coefs: (n+1, 3), coefficient of t^i in row i."""
    n = coefs.shape[0] - 1
    parts = []
    for k, ax in enumerate("XYZ"):
        parts.append(f'<{ax} order1="{n}">' + "".join(
            f'<Coef exponent1="{i}">{_f(coefs[i, k])}</Coef>' for i in range(n + 1)) + f"</{ax}>")
    return f"<{tag}>" + "".join(parts) + f"</{tag}>"


def _fit_positions(t: np.ndarray, pos: np.ndarray, order: int = 5):
    """Least-squares polynomial (t in s) through the positions; coefficients (order+1, 3) and the
    largest residual (m)."""
    order = int(min(order, t.size - 1))
    ts = max(float(np.max(np.abs(t))), 1e-12)
    V = np.vander(t / ts, order + 1, increasing=True)
    c, *_ = np.linalg.lstsq(V, pos, rcond=None)
    res = float(np.max(np.abs(V @ c - pos)))
    c = c / (ts ** np.arange(order + 1))[:, None]
    return c, res


def sicd_xml(image: xr.Dataset, origin=None, core_name: str = "salkit"):
    """The SICD XML tree of a salkit image (SCPCOA computed by sarkit).

    Parameters
    ----------
    image : xarray.Dataset
        salkit image with ``collection_position`` and ``collection_time``.
    origin : (lat deg, lon deg, hae m), optional
        Geodetic position of the scene centre (default the image's ``origin_llh``, else 0, 0, 0: the
        command line refuses that, naming ``--origin``).
    core_name : str
        CollectionInfo/CoreName.

    Returns
    -------
    tree : lxml.etree.ElementTree
    info : dict
        ``position_fit_residual`` (m, largest deviation of ARPPoly from the antenna positions) and
        ``columns_flipped`` (SICD columns run along -azimuth).

    Raises
    ------
    DataFileError
        An image without the collection geometry.
    """
    import lxml.etree as et
    import sarkit.sicd as sksicd
    import sarkit.wgs84 as wgs84

    for v in ("collection_position", "collection_time"):
        if v not in image:
            raise DataFileError(f"SICD export needs the variable '{v}' (images from salkit >= 0.5 carry it; "
                                "focus the raw file again)")
    a = image.attrs
    az, rg = image["azimuth"].values, image["range"].values
    nx, ny = az.size, rg.size
    # an origin given explicitly wins over the image's own
    llh = np.asarray(origin if origin is not None else a.get("origin_llh", DEFAULT_ORIGIN), np.float64)
    o_ecf, rot = local_frame(llh)
    u_az = rot @ np.asarray(a["azimuth_axis"], np.float64)
    u_rg = rot @ np.asarray(a["range_axis"], np.float64)
    # SICD wants uRow x uCol pointing away from the earth: columns run along -azimuth when the
    # platform looks left of its track (the pixel array is then flipped along columns)
    flip = float(np.cross(u_rg, u_az) @ (o_ecf / np.linalg.norm(o_ecf))) < 0
    if flip:
        u_az = -u_az
    origin_l = np.asarray(a.get("plane_origin", np.zeros(3)), np.float64)

    def to_ecf(A, R):
        return o_ecf + (origin_l + np.multiply.outer(A, a["azimuth_axis"]) + np.multiply.outer(R, a["range_axis"])) @ rot.T

    scp = to_ecf(az[nx // 2], rg[ny // 2])
    scp_llh = wgs84.cartesian_to_geodetic(scp)
    t = np.asarray(image["collection_time"].values, np.float64)
    t = t - t[0]
    pos = o_ecf + np.asarray(image["collection_position"].values, np.float64) @ rot.T
    coefs, fit_res = _fit_positions(t, pos)
    t_scp = float(t[t.size // 2])
    fmin, fmax = float(a["frequency_min"]), float(a["frequency_max"])
    fc = 0.5 * (fmin + fmax)
    look = (pos[t.size // 2] - scp) / np.linalg.norm(pos[t.size // 2] - scp)  # scene -> antenna
    sin_graze = float(look @ wgs84.up(scp_llh))
    if sin_graze < 1e-4:
        raise DataFileError(f"SICD describes imaging of the earth's surface from above: the antenna is "
                            f"{np.degrees(np.arcsin(np.clip(sin_graze, -1, 1))):.4f} deg above the scene's "
                            "horizon (grazing angle must exceed 0.006 deg); export the phase history as "
                            "CPHD instead")
    cos_r = abs(float(look @ u_rg))
    dy, dx = float(rg[1] - rg[0]), float(az[1] - az[0])
    bw_r, bw_a = 1.0 / float(a["resolution_range"]), 1.0 / float(a["resolution_azimuth"])
    win = WINDOWS.get(str(a.get("window", "none")), "UNKNOWN")
    # placeholder corners (image-plane points); replaced below by their projection to the SCP height
    a0, a1 = (az[-1], az[0]) if flip else (az[0], az[-1])
    corners = [to_ecf(a0, rg[0]), to_ecf(a1, rg[0]), to_ecf(a1, rg[-1]), to_ecf(a0, rg[-1])]
    cll = wgs84.cartesian_to_geodetic(np.array(corners))
    icp = "".join(f'<ICP index="{k}"><Lat>{_f(cll[i, 0])}</Lat><Lon>{_f(cll[i, 1])}</Lon></ICP>'
                  for i, k in enumerate(("1:FRFC", "2:FRLC", "3:LRLC", "4:LRFC")))
    # the imaged area's corners (RadarCollection/Area): the image corners at the SCP's height
    acp = "".join(f'<ACP index="{k + 1}"><Lat>{_f(cll[k, 0])}</Lat><Lon>{_f(cll[k, 1])}</Lon>'
                  f'<HAE>{_f(scp_llh[2])}</HAE></ACP>' for k in range(4))
    plane = {"slant": "SLANT", "ground": "GROUND"}.get(str(a.get("plane", "slant")), "OTHER")
    mode = "SPOTLIGHT" if str(a.get("mode", "spotlight")) == "spotlight" else "STRIPMAP"
    af = "GLOBAL" if a.get("autofocus") not in (None, "", "none") else "NO"
    now = _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%dT%H:%M:%S.%fZ")

    def dirparam(tag, u, ss, bw, kctr, irw):
        return (f"<{tag}>{_xyz('UVectECF', u)}<SS>{_f(ss)}</SS><ImpRespWid>{_f(irw)}</ImpRespWid><Sgn>-1</Sgn>"
                f"<ImpRespBW>{_f(bw)}</ImpRespBW><KCtr>{_f(kctr)}</KCtr><DeltaK1>{_f(-bw / 2)}</DeltaK1>"
                f"<DeltaK2>{_f(bw / 2)}</DeltaK2><WgtType><WindowName>{win}</WindowName></WgtType></{tag}>")

    xml = f"""<SICD xmlns="{NS}">
<CollectionInfo><CollectorName>salkit</CollectorName><CoreName>{core_name}</CoreName><CollectType>MONOSTATIC</CollectType>
<RadarMode><ModeType>{mode}</ModeType></RadarMode><Classification>UNCLASSIFIED</Classification></CollectionInfo>
<ImageCreation><Application>salkit {a.get('salkit_version', '')}</Application><DateTime>{now}</DateTime><Site>salkit</Site>
<Profile>salkit image {a.get('algorithm', '')}</Profile></ImageCreation>
<ImageData><PixelType>RE32F_IM32F</PixelType><NumRows>{ny}</NumRows><NumCols>{nx}</NumCols><FirstRow>0</FirstRow>
<FirstCol>0</FirstCol><FullImage><NumRows>{ny}</NumRows><NumCols>{nx}</NumCols></FullImage>
<SCPPixel><Row>{ny // 2}</Row><Col>{nx - 1 - nx // 2 if flip else nx // 2}</Col></SCPPixel></ImageData>
<GeoData><EarthModel>WGS_84</EarthModel><SCP>{_xyz('ECF', scp)}<LLH><Lat>{_f(scp_llh[0])}</Lat><Lon>{_f(scp_llh[1])}</Lon>
<HAE>{_f(scp_llh[2])}</HAE></LLH></SCP><ImageCorners>{icp}</ImageCorners></GeoData>
<Grid><ImagePlane>{plane}</ImagePlane><Type>PLANE</Type>
<TimeCOAPoly order1="0" order2="0"><Coef exponent1="0" exponent2="0">{_f(t_scp)}</Coef></TimeCOAPoly>
{dirparam('Row', u_rg, dy, bw_r, 2 * fc / SPEED_OF_LIGHT * cos_r, _rect_irw(a, 'range', bw_r))}
{dirparam('Col', u_az, dx, bw_a, 0.0, _rect_irw(a, 'azimuth', bw_a))}</Grid>
<Timeline><CollectStart>2000-01-01T00:00:00.000000Z</CollectStart><CollectDuration>{_f(t[-1])}</CollectDuration></Timeline>
<Position>{_xyzpoly('ARPPoly', coefs)}</Position>
<RadarCollection><TxFrequency><Min>{_f(fmin)}</Min><Max>{_f(fmax)}</Max></TxFrequency><TxPolarization>UNKNOWN</TxPolarization>
<RcvChannels size="1"><ChanParameters index="1"><TxRcvPolarization>UNKNOWN</TxRcvPolarization></ChanParameters></RcvChannels>
<Area><Corner>{acp}</Corner></Area>
</RadarCollection>
<ImageFormation><RcvChanProc><NumChanProc>1</NumChanProc><ChanIndex>1</ChanIndex></RcvChanProc>
<TxRcvPolarizationProc>UNKNOWN</TxRcvPolarizationProc><TStartProc>0.0</TStartProc><TEndProc>{_f(t[-1])}</TEndProc>
<TxFrequencyProc><MinProc>{_f(fmin)}</MinProc><MaxProc>{_f(fmax)}</MaxProc></TxFrequencyProc>
<ImageFormAlgo>OTHER</ImageFormAlgo><STBeamComp>NO</STBeamComp><ImageBeamComp>NO</ImageBeamComp>
<AzAutofocus>{af}</AzAutofocus><RgAutofocus>NO</RgAutofocus></ImageFormation>
<SCPCOA/>
</SICD>"""
    root = et.fromstring(xml.encode())
    tree = et.ElementTree(root)
    root.replace(root.find(f"{{{NS}}}SCPCOA"), sksicd.compute_scp_coa(tree))
    # image corners: the corner pixels projected to the SCP's height (SICD volume 3)
    rc = np.array([[0, 0], [0, nx - 1], [ny - 1, nx - 1], [ny - 1, 0]])
    xy = sksicd.rowcol_to_xrowycol(tree, rc)
    gpp, _, ok = sksicd.image_to_constant_hae_surface(tree, xy, float(scp_llh[2]))
    if ok:
        ll = wgs84.cartesian_to_geodetic(gpp)
        for i, icp in enumerate(root.find(f"{{{NS}}}GeoData/{{{NS}}}ImageCorners")):
            icp.find(f"{{{NS}}}Lat").text = _f(ll[i, 0])
            icp.find(f"{{{NS}}}Lon").text = _f(ll[i, 1])
        for i, acp in enumerate(root.find(f"{{{NS}}}RadarCollection/{{{NS}}}Area/{{{NS}}}Corner")):
            acp.find(f"{{{NS}}}Lat").text = _f(ll[i, 0])
            acp.find(f"{{{NS}}}Lon").text = _f(ll[i, 1])
    return tree, {"position_fit_residual": fit_res, "columns_flipped": bool(flip)}


def write_sicd(image: xr.Dataset, path: str | Path, origin=None) -> Path:
    """Write a salkit image as a SICD 1.3.0 NITF file (atomically).

    Parameters
    ----------
    image : xarray.Dataset
        salkit image (``docs/data-format.md``) with its collection geometry.
    path : str or Path
        ``.nitf`` (or ``.ntf``) file to write.
    origin : (lat deg, lon deg, hae m), optional
        Geodetic position of the scene centre.

    Returns
    -------
    Path
    """
    import sarkit.sicd as sksicd

    tree, info = sicd_xml(image, origin, core_name=Path(path).stem[:80] or "salkit")
    sec = sksicd.NitfSecurityFields(clas="U")
    meta = sksicd.NitfMetadata(
        xmltree=tree,
        file_header_part=sksicd.NitfFileHeaderPart(ostaid="salkit", security=sec),
        im_subheader_part=sksicd.NitfImSubheaderPart(isorce="salkit simulation or outside data", security=sec),
        de_subheader_part=sksicd.NitfDeSubheaderPart(security=sec))
    pix = np.asarray(image["image"].values, np.complex64).T  # (range, azimuth)
    if info["columns_flipped"]:
        pix = pix[:, ::-1]
    pix = np.ascontiguousarray(pix)
    with atomic_path(path, suffix=".nitf") as tmp:
        with open(tmp, "wb") as fh, sksicd.NitfWriter(fh, meta) as w:
            w.write_image(pix)
    return Path(path)


def read_sicd(path: str | Path) -> tuple[np.ndarray, "object"]:
    """Read a SICD NITF: the complex pixels (rows = range, columns = azimuth) and the XML tree.

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    (ndarray complex64 (NumRows, NumCols), lxml.etree.ElementTree)
    """
    path = input_file(path)
    import sarkit.sicd as sksicd
    try:
        with open(path, "rb") as fh, sksicd.NitfReader(fh) as r:
            return np.asarray(r.read_image()), r.metadata.xmltree
    except Exception as e:  # noqa: BLE001
        raise DataFileError(f"{path}: cannot be read as SICD: {type(e).__name__}: {e}") from None


def check_sicd(path: str | Path) -> dict:
    """Run sarkit's SICD consistency checker (schema included).

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    dict
        ``errors`` and ``warnings``: lists of "check: requirement" lines.
    """
    from sarkit.verification import SicdConsistency
    return run_checker(SicdConsistency, path)


__all__ = ["check_sicd", "read_sicd", "sicd_xml", "write_sicd"]
