//! Light sources: area, point, spot, distant, infinite.
