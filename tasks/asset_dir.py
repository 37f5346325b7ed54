"""One typed reader / writer of an asset directory: the way a layer reads what an earlier layer wrote.

    adir = AssetDir(path)
    adir.physical().physical_model       # validated PhysicalRecord (InputError naming the file when absent / invalid)
    adir.physical_model()                # the frozen L1 model (InputError when L1 has not run or failed)
    adir.adopted_material().material     # the asset's one final material: L2's, or the L3 revision L3 passed with
    adir.write_physical(record)          # validated, atomically, as sorted indented JSON

Documents and file names are in contracts/asset_dir.py; a document read and written back is the same JSON.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, TypeVar

from pydantic import BaseModel, ValidationError

from contracts.asset_dir import (
    DOCUMENT_FILES,
    DOCUMENT_MODELS,
    GEOMETRY_JSON,
    MANIPULATION_JSON,
    MATERIAL_JSON,
    AdoptedMaterial,
    DocumentName,
    GeometryInfo,
    GeometryRecord,
    ManipulationRecord,
    MaterialRecord,
    PhysicalRecord,
)
from contracts.errors import InputError, validation_message
from contracts.manifest import AssetManifest
from contracts.material import Material
from contracts.physical import PhysicalModel
from tasks.publish import write_json_atomic

D = TypeVar("D", bound=BaseModel)


def _missing_hint(name: DocumentName, root: Path) -> str:
    """What to run when a document is missing (the messages the layers' loaders always gave)."""
    return {
        "geometry": f"{root} is not an L0 output directory (no {DOCUMENT_FILES['geometry']})",
        "physical": f"{root} has no {DOCUMENT_FILES['physical']}: run `deformsmith physical --asset {root}` first",
        "material": f"{root} has no {DOCUMENT_FILES['material']}: run `deformsmith material --asset {root}` first",
        "manipulation": f"{root} has no {DOCUMENT_FILES['manipulation']}: run `deformsmith manipulate {root}` first",
        "manifest": f"{root} is not an asset directory (no {DOCUMENT_FILES['manifest']})",
    }[name]


def _json_default(o: Any) -> Any:
    """JSON for numpy values (arrays and scalars) and anything else as its string."""
    if hasattr(o, "tolist"):
        return o.tolist()
    return str(o)


def document_json(doc: BaseModel) -> dict[str, Any]:
    """A document as the JSON object its layer writes: every field (defaults included), nested models in full, NaN
    kept as NaN; a key older records lack (the model's ABSENT_UNLESS_GIVEN) stays absent unless it was given."""
    out = doc.model_dump(mode="python")
    for key in getattr(doc, "ABSENT_UNLESS_GIVEN", ()):
        if key not in doc.model_fields_set:
            out.pop(key, None)
    return out


class AssetDir:
    """An asset directory (a working or a published one) and its typed documents."""

    def __init__(self, path: Path | str) -> None:
        self.path = Path(path)

    def __repr__(self) -> str:
        return f"AssetDir({str(self.path)!r})"

    def file(self, name: DocumentName) -> Path:
        """The path of a document."""
        return self.path / DOCUMENT_FILES[name]

    def has(self, name: DocumentName) -> bool:
        """True when the document's file exists (it may still be invalid)."""
        return self.file(name).is_file()

    def read(self, name: DocumentName, model: type[D]) -> D:
        """A document, validated (InputError naming the file when it is missing, not JSON or not the document)."""
        path = self.file(name)
        if not path.is_file():
            raise InputError(_missing_hint(name, self.path))
        try:
            return model.model_validate(json.loads(path.read_text(encoding="utf-8")))
        except json.JSONDecodeError as exc:
            raise InputError(f"{path}: not valid JSON: {exc}") from None
        except ValidationError as exc:
            raise InputError(f"{path}: not a valid {name} document: {validation_message(exc, limit=5)}") from None

    # -- documents ---------------------------------------------------------------------------------------------------
    def geometry(self) -> GeometryRecord:
        """geometry.json (L0)."""
        return self.read("geometry", GeometryRecord)

    def physical(self) -> PhysicalRecord:
        """physical.json (L1)."""
        return self.read("physical", PhysicalRecord)

    def material(self) -> MaterialRecord:
        """material.json (L2)."""
        return self.read("material", MaterialRecord)

    def manipulation(self) -> ManipulationRecord:
        """manipulation.json (L3)."""
        return self.read("manipulation", ManipulationRecord)

    def manifest(self) -> AssetManifest:
        """asset.json (the published manifest)."""
        return self.read("manifest", AssetManifest)

    # -- what later layers use ---------------------------------------------------------------------------------------
    def physical_model(self) -> PhysicalModel:
        """The frozen L1 model (InputError when L1 has not run or failed)."""
        record = self.physical()
        if record.physical_model is None:
            raise InputError(f"{self.file('physical')}: L1 did not produce a valid physical model "
                             f"({record.message or 'failed'})")
        return record.physical_model

    def material_model(self) -> Material:
        """L2's material, where L3 starts (InputError when L2 has not run or found none); the asset's final material
        is adopted_material()."""
        record = self.material()
        if record.material is None:
            raise InputError(f"{self.file('material')}: L2 found no valid material ({record.message or 'failed'})")
        return record.material

    def adopted_material(self) -> AdoptedMaterial:
        """The asset's final material, which the manifest, exports, PhysGaussian config and card all carry: the L3
        revision when L3 passed with one, else L2's (InputError when there is neither)."""
        revision = self._l3_revision()
        if revision is not None:
            return revision
        record = self.material()
        return AdoptedMaterial(material=self.material_model(), source="L2", document=MATERIAL_JSON,
                               reason=f"L2's selection ({record.status})", metrics=dict(record.metrics))

    def _l3_revision(self) -> AdoptedMaterial | None:
        """The material revision L3 adopted (it passed with it: manipulation.json), else None."""
        if not self.has("manipulation"):
            return None
        record = self.manipulation()
        revision = record.adopted_revision()
        if revision is None:
            return None
        return AdoptedMaterial(material=record.material, source="L3 revision", document=MANIPULATION_JSON,
                               reason=f"L3 material revision ({revision.trigger}; L2 revalidated, robot confirmed): "
                                      f"{revision.reason}",
                               metrics=dict(revision.l2_revalidation.metrics))

    # -- writers -----------------------------------------------------------------------------------------------------
    def write(self, name: DocumentName, doc: BaseModel) -> Path:
        """Write a document (validated: it must be the document's model) atomically; returns its path."""
        model = DOCUMENT_MODELS[name]
        if not isinstance(doc, model):
            raise TypeError(f"{DOCUMENT_FILES[name]} takes a {model.__name__}, got {type(doc).__name__}")
        path = self.file(name)
        path.parent.mkdir(parents=True, exist_ok=True)
        if name == "manifest":  # asset.json: pydantic's own JSON (a NaN would not load back)
            tmp = path.with_name(path.name + ".tmp")
            tmp.write_text(doc.model_dump_json(indent=2) + "\n", encoding="utf-8")
            tmp.replace(path)
        else:
            write_json_atomic(path, document_json(doc), default=_json_default)
        return path

    def write_geometry(self, record: GeometryRecord) -> Path:
        """Write geometry.json."""
        return self.write("geometry", record)

    def write_physical(self, record: PhysicalRecord) -> Path:
        """Write physical.json."""
        return self.write("physical", record)

    def write_material(self, record: MaterialRecord) -> Path:
        """Write material.json."""
        return self.write("material", record)

    def write_manipulation(self, record: ManipulationRecord) -> Path:
        """Write manipulation.json."""
        return self.write("manipulation", record)

    def write_manifest(self, manifest: AssetManifest) -> Path:
        """Write asset.json."""
        return self.write("manifest", manifest)


def geometry_info(record: dict[str, Any]) -> GeometryInfo:
    """The build information of a geometry.json record (L0Asset.record), typed (InputError when it has none)."""
    try:
        return GeometryInfo.model_validate(record.get("info"))
    except ValidationError as exc:
        raise InputError(f"{GEOMETRY_JSON} info: {validation_message(exc, limit=5)}") from None
