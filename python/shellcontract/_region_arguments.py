"""contract()'s region arguments checked and converted, by Python's indices: face lists or one
label per face (regions), a strength per region (region_strengths), a weight per vertex
(region_weights). Private to the package (__init__.py)."""
import numbers

import numpy as np


def refuse_masked(value, name):
    """A numpy masked array with a masked element is refused: numpy hands on its data, masked
    entries included, so a masked vertex, label or weight would be used as whatever value hides
    under the mask (a label moved faces between regions). One without a masked element is its
    data. Nested lists and sequences are walked one level (regions as a list of arrays)."""
    if np.ma.isMaskedArray(value) and np.ma.is_masked(value):
        raise ValueError("{}: a masked array with masked elements; numpy would pass on the values "
                         "under the mask: fill them (a.filled(...)) or leave them out first".format(name))
    if isinstance(value, (list, tuple)):
        for i, item in enumerate(value):
            if np.ma.isMaskedArray(item) and np.ma.is_masked(item):
                refuse_masked(item, "{}[{}]".format(name, i))


def _weights(weights):
    """One float per vertex as a 1-D float64 array; the range is the library's to check (it names
    the vertex). A 2-D array, strings, bools or complex numbers are not weights, whatever their
    count (numpy would flatten or convert them)."""
    refuse_masked(weights, "region_weights")
    if isinstance(weights, (str, bytes)):
        raise TypeError("region_weights: expected a file name or one number per vertex")
    a = np.asarray(weights)
    if a.ndim != 1:
        raise TypeError("region_weights: expected one number per vertex (a list or a 1-D array), "
                        "got an array of shape {}".format(a.shape))
    if a.dtype.kind == "O":  # Python numbers numpy cannot hold as one type (an int past 2^64)
        for i, w in enumerate(a):
            if isinstance(w, (bool, np.bool_)) or not isinstance(w, numbers.Real):
                raise TypeError("region_weights[{}] = {!r} is not a number".format(i, w))
            try:
                float(w)
            except OverflowError:
                raise ValueError("region_weights[{}] = {} is not a weight in [0, 1]".format(i, w))
    elif a.dtype.kind not in "iuf":
        raise TypeError("region_weights: expected numbers, got an array of {}".format(a.dtype))
    return a.astype(np.float64)


def _strengths(strengths, num_regions):
    """One float in [0, 1] per region (the share of region_shrink each region sinks with)."""
    refuse_masked(strengths, "region_strengths")
    try:
        ndim = np.ndim(strengths)
    except ValueError:  # ragged: numpy cannot make it one array
        ndim = None
    if isinstance(strengths, (str, bytes)) or ndim != 1:
        raise TypeError("region_strengths: expected one number per region (a list or a 1-D array), "
                        "got {!r}".format(strengths))
    if any(isinstance(s, (bool, np.bool_)) for s in strengths):
        raise TypeError("region_strengths: expected numbers in [0, 1], not bools")
    for i, s in enumerate(strengths):
        if not isinstance(s, numbers.Real):  # "0.5" would pass float(); a str is not a strength
            raise TypeError("region_strengths[{}] = {!r} is not a number".format(i, s))
    values = [float(s) for s in strengths]
    if len(values) != num_regions:
        raise ValueError("region_strengths: {} values for {} regions".format(len(values), num_regions))
    for i, s in enumerate(values):
        if not 0.0 <= s <= 1.0:  # NaN fails too
            raise ValueError("region_strengths[{}] = {!r} is outside [0, 1]".format(i, s))
    return values


_REGIONS_FORMS = ("regions: expected 'auto', 'none' or a face-list file (str or os.PathLike), one "
                  "label per face (a 1-D numpy integer array or a flat list of ints) or a list of "
                  "face-index sequences")


def _is_int(x):
    # bool is an Integral, but True as face 1 is a mistake, not a face.
    return isinstance(x, numbers.Integral) and not isinstance(x, bool)


def _region_lists(regions, num_faces):
    """Face lists (one int64 array per region) from the forms contract() documents: a per-face
    label array, or a list of face-index sequences. Checked here, by Python's indices, so that no
    error names the temporary face-list file the library then reads."""
    refuse_masked(regions, "regions")
    if isinstance(regions, np.ndarray):
        if regions.ndim == 1 and np.issubdtype(regions.dtype, np.integer):
            return _labels_to_lists(regions, num_faces)
        raise TypeError(_REGIONS_FORMS + "; got a {}-D {} array".format(regions.ndim, regions.dtype))
    if not isinstance(regions, (list, tuple)):
        raise TypeError(_REGIONS_FORMS + "; got {}".format(type(regions).__name__))
    if not regions:
        return []
    if all(_is_int(x) for x in regions):
        return _labels_to_lists(np.array(regions, dtype=object), num_faces)
    if all(_is_sequence(r) for r in regions):
        return _face_lists(regions, num_faces)
    # Neither form: name the first item that fits neither, or that breaks regions[0]'s form.
    k = next((k for k, x in enumerate(regions) if not (_is_int(x) or _is_sequence(x))), None)
    if k is not None:
        why = "neither an int label nor a sequence of face indices"
    else:
        k = next(k for k, x in enumerate(regions) if _is_int(x) != _is_int(regions[0]))
        why = "in a list whose regions[0] is " + ("an int label" if _is_int(regions[0]) else "a sequence")
    raise TypeError(_REGIONS_FORMS + "; got regions[{}] = {!r} ({}), {}"
                    .format(k, regions[k], type(regions[k]).__name__, why))


def _is_sequence(x):
    return isinstance(x, (list, tuple, range, np.ndarray))


def _labels_to_lists(labels, num_faces):
    """Face lists from one label per face (-1 = no region, labels 0..n-1 without a gap)."""
    if len(labels) != num_faces:
        raise ValueError("regions: a label array needs one entry per face ({} faces, {} labels)"
                         .format(num_faces, len(labels)))
    # Compared before any conversion (Python ints of any size, in an object array, or a uint64
    # array), so that no value wraps; a label >= the face count leaves a gap below it.
    bad = np.flatnonzero((labels < -1) | (labels >= num_faces))
    if len(bad):
        raise ValueError("regions: face {} has label {}; labels are -1 (no region) or 0..n-1 without a "
                         "gap".format(bad[0], labels[bad[0]]))
    labels = labels.astype(np.int64)
    counts = np.bincount(labels[labels >= 0])
    if counts.size == 0:
        return []
    if np.any(counts == 0):
        raise ValueError("regions: labels must be 0..n-1 without a gap (no face has label {})"
                         .format(np.flatnonzero(counts == 0)[0]))
    order = np.argsort(labels, kind="stable")
    return np.split(order[len(labels) - counts.sum():], np.cumsum(counts)[:-1])


def _face_lists(regions, num_faces):
    """The regions as int64 arrays after checking each face: an integer, in range, in one region
    at most; and no region empty (the file's empty line would shift the later regions)."""
    out = []
    owner = np.full(num_faces, -1, dtype=np.int64)
    for k, r in enumerate(regions):
        if isinstance(r, np.ndarray):
            if r.ndim != 1 or not (np.issubdtype(r.dtype, np.integer) or r.size == 0):
                raise TypeError("regions[{}]: expected a 1-D array of integer face indices, got a {}-D {} "
                                "array".format(k, r.ndim, r.dtype))
            faces = list(r.tolist())
        else:
            faces = list(r)
            for i, f in enumerate(faces):
                if not _is_int(f):
                    raise TypeError("regions[{}][{}] = {!r}: face indices must be integers, not {}"
                                    .format(k, i, f, type(f).__name__))
        if not faces:
            raise ValueError("regions[{}] is empty: every region needs at least one face".format(k))
        for f in faces:
            if not 0 <= f < num_faces:
                raise ValueError("regions[{}]: face {} is out of range (the mesh has {} faces: 0..{})"
                                 .format(k, f, num_faces, num_faces - 1))
            if owner[f] >= 0:
                where = "twice in it" if owner[f] == k else "also in regions[{}]".format(owner[f])
                raise ValueError("regions[{}]: face {} is {}".format(k, f, where))
            owner[f] = k
        out.append(np.array(faces, dtype=np.int64))
    return out
