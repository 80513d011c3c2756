"""JSON Schemas (draft-07) of the robot description and study formats, for editors; generated
by ``planar_sym.study.schema`` (``planar-sym schema``), never edited by hand."""
