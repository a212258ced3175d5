//! The untyped syntax tree: what was written, with spans, before names, units and
//! physics are checked. Numbers keep their source text so the formatter prints
//! them exactly as written.

use crate::span::Span;

#[derive(Debug, Clone, PartialEq)]
pub struct Ident {
    pub name: String,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub struct File {
    pub items: Vec<Item>,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Item {
    pub kind: ItemKind,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub enum ItemKind {
    Model(Ident),
    Import(Ident),
    DefaultLoads(Ident),
    Param(ParamDecl),
    Part(PartDecl),
    Element(ElementDecl),
    Loads(LoadsDecl),
    Template(TemplateDecl),
    Instance(InstanceDecl),
}

/// `template NAME(p1, p2 = default) { items }`: a group of parts and elements
/// stamped out by every `instance` of it (see `check::expand`).
#[derive(Debug, Clone, PartialEq)]
pub struct TemplateDecl {
    pub name: Ident,
    pub params: Vec<TemplateParam>,
    /// The parameter list with its brackets.
    pub params_span: Span,
    /// Params, parts, elements and nested instances (never models, imports,
    /// loads or templates).
    pub items: Vec<Item>,
}

/// A template parameter, used in the body like a `param`.
#[derive(Debug, Clone, PartialEq)]
pub struct TemplateParam {
    pub name: Ident,
    pub default: Option<Expr>,
    pub span: Span,
}

/// `instance NAME = [mirror] TEMPLATE(arg = value, ...)`.
#[derive(Debug, Clone, PartialEq)]
pub struct InstanceDecl {
    pub name: Ident,
    /// Reflected about the vehicle xz plane (y -> -y).
    pub mirror: bool,
    pub template: Ident,
    pub args: Vec<Argument>,
    /// The argument list with its brackets.
    pub args_span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Argument {
    pub name: Ident,
    pub value: Expr,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub struct ParamDecl {
    pub name: Ident,
    pub value: Expr,
    pub unknown: Option<Unknown>,
}

/// `unknown` with optional `[lower, upper]`; `None` bounds are open (`_`).
#[derive(Debug, Clone, PartialEq)]
pub struct Unknown {
    pub bounds: Option<(Option<Expr>, Option<Expr>)>,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub struct PartDecl {
    pub ground: bool,
    /// The `ground` or `part` keyword.
    pub keyword_span: Span,
    pub name: Ident,
    pub items: Vec<PartItem>,
}

#[derive(Debug, Clone, PartialEq)]
pub enum PartItem {
    Marker(MarkerDecl),
    Landmark(LandmarkDecl),
}

impl PartItem {
    /// The marker's or landmark's name.
    pub fn name(&self) -> &Ident {
        match self {
            PartItem::Marker(m) => &m.name,
            PartItem::Landmark(l) => &l.name,
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct MarkerDecl {
    pub name: Ident,
    pub at: Vector,
    pub orient: Option<Orient>,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub enum Orient {
    Euler(Vector),
    Directions { z: Vector, x: Option<Vector> },
}

#[derive(Debug, Clone, PartialEq)]
pub struct LandmarkDecl {
    pub name: Ident,
    pub at: Vector,
    pub span: Span,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ElementKw {
    Joint,
    Bushing,
    Spring,
    Stop,
    Friction,
    Wheel,
}

impl ElementKw {
    /// Every element kind (a test holds this to the grammar's `element_kw`).
    pub const ALL: &[ElementKw] = &[
        ElementKw::Joint,
        ElementKw::Bushing,
        ElementKw::Spring,
        ElementKw::Stop,
        ElementKw::Friction,
        ElementKw::Wheel,
    ];

    pub fn from_keyword(word: &str) -> Option<ElementKw> {
        Self::ALL.iter().copied().find(|k| k.keyword() == word)
    }

    pub fn keyword(self) -> &'static str {
        match self {
            ElementKw::Joint => "joint",
            ElementKw::Bushing => "bushing",
            ElementKw::Spring => "spring",
            ElementKw::Stop => "stop",
            ElementKw::Friction => "friction",
            ElementKw::Wheel => "wheel",
        }
    }
}

/// `joint L8 spherical { i front_arm.L8 \n j upright.L8 }`.
#[derive(Debug, Clone, PartialEq)]
pub struct ElementDecl {
    pub keyword: ElementKw,
    pub name: Ident,
    /// The sub-kind word: a joint kind, or a stop's `compression`/`rebound`.
    pub kind: Option<Ident>,
    pub props: Vec<Property>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Property {
    pub key: Ident,
    pub value: Value,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    Ref(MarkerRef),
    Vector(Vector),
    Table(TableLit),
    List(Vec<Expr>, Span),
    Expr(Expr),
}

impl Value {
    pub fn span(&self) -> Span {
        match self {
            Value::Ref(r) => r.span,
            Value::Vector(v) => v.span,
            Value::Table(t) => t.span,
            Value::List(_, s) => *s,
            Value::Expr(e) => e.span,
        }
    }
}

/// `part.marker`; `part` may be qualified (`front_left.upright`), its span
/// then covers every name before the marker.
#[derive(Debug, Clone, PartialEq)]
pub struct MarkerRef {
    pub part: Ident,
    pub marker: Ident,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub struct UnitLit {
    pub text: String,
    pub span: Span,
}

/// `(a, b, c) unit`.
#[derive(Debug, Clone, PartialEq)]
pub struct Vector {
    pub comps: [Expr; 3],
    pub unit: Option<UnitLit>,
    pub span: Span,
}

/// A number as written.
#[derive(Debug, Clone, PartialEq)]
pub struct Num {
    pub value: f64,
    pub text: String,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub struct TableLit {
    pub x_unit: UnitLit,
    pub y_unit: UnitLit,
    pub points: Vec<(Num, Num)>,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Expr {
    pub kind: ExprKind,
    pub span: Span,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BinOp {
    Add,
    Sub,
    Mul,
    Div,
}

impl BinOp {
    pub fn symbol(self) -> &'static str {
        match self {
            BinOp::Add => "+",
            BinOp::Sub => "-",
            BinOp::Mul => "*",
            BinOp::Div => "/",
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
pub enum ExprKind {
    Quantity { num: Num, unit: Option<UnitLit> },
    Param(Ident),
    Neg(Box<Expr>),
    Binary(BinOp, Box<Expr>, Box<Expr>),
    Pow(Box<Expr>, Num),
    Call(Ident, Vec<Expr>),
    Paren(Box<Expr>),
}

#[derive(Debug, Clone, PartialEq)]
pub struct LoadsDecl {
    pub name: Ident,
    pub body: LoadsBody,
}

#[derive(Debug, Clone, PartialEq)]
pub enum LoadsBody {
    Table {
        columns: Vec<Column>,
        rows: Vec<Row>,
    },
    Sweep {
        lines: Vec<SweepLine>,
    },
}

/// A load channel as written: `fz`, `left.fz`, `arm.tip.fx`.
#[derive(Debug, Clone, PartialEq)]
pub struct ChannelLit {
    pub path: Vec<String>,
    pub span: Span,
}

impl ChannelLit {
    pub fn text(&self) -> String {
        self.path.join(".")
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct Column {
    pub channel: ChannelLit,
    pub unit: UnitLit,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    pub name: Ident,
    pub values: Vec<Num>,
    pub span: Span,
}

/// `fy 0 N -> 4000 N by 250 N` (or one value: a constant channel).
#[derive(Debug, Clone, PartialEq)]
pub struct SweepLine {
    pub channel: ChannelLit,
    pub waypoints: Vec<Expr>,
    pub step: Option<Expr>,
    pub span: Span,
}
