//! Reading what JavaScript passes in (parameter objects, ids, byte arrays) without recursion,
//! without coercion and without letting a JavaScript exception unwind through Rust.
//!
//! The release build aborts on panic and runs no Rust code while a JavaScript exception
//! unwinds through wasm frames: a borrow of `self` taken by the generated shim and the wasm
//! shadow stack would both stay taken. So every read here goes through an import declared
//! with `catch` (`Reflect.get`, `Reflect.ownKeys`, `Array.isArray`) or through a
//! wasm-bindgen intrinsic that cannot throw (`typeof` checks), and a getter or Proxy trap that
//! throws becomes an ordinary `Err` naming the parameter.
//!
//! Parameter objects are read by [`ParamReader`]: only the keys the caller asks for, each
//! type-checked, nested objects only as deep as the caller's schema and at most
//! [`MAX_DEPTH`]; every other own key is refused by name without reading its value, so a
//! cycle or a 5,000-deep object costs nothing.

use crate::math::Compact;
use js_sys::{JsString, Reflect, Uint8Array};
use wasm_bindgen::prelude::*;
use wasm_bindgen::JsCast;

/// Deepest parameter object a schema may read (top level is depth 0).
pub const MAX_DEPTH: usize = 4;
/// Longest string a parameter may hold, in UTF-16 units (names, choices).
const MAX_STRING: u32 = 256;
/// Characters of a foreign string or exception message quoted back in a message.
const QUOTE_CHARS: u32 = 40;

#[wasm_bindgen]
extern "C" {
    /// `Array.isArray`, which throws for a revoked Proxy: hence `catch`.
    #[wasm_bindgen(catch, js_namespace = Array, js_name = isArray)]
    fn is_array(value: &JsValue) -> Result<bool, JsValue>;
}

/// A JavaScript argument was refused; the message names it, what was given and what is allowed.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct ArgError(
    /// The message, as JavaScript will see it.
    pub String,
);

/// How a value is named in a message: `null`, `the string "0.35"`, `an array`, `a Blob`.
pub(crate) fn describe(value: &JsValue) -> String {
    if value.is_undefined() {
        return "undefined".into();
    }
    if value.is_null() {
        return "null".into();
    }
    if let Some(b) = value.as_bool() {
        return format!("{b}");
    }
    if let Some(x) = value.as_f64() {
        return format!("the number {}", Compact(x));
    }
    if value.is_string() {
        return format!("the string {}", quote(value.unchecked_ref::<JsString>()));
    }
    if value.is_bigint() {
        return "a BigInt".into();
    }
    if value.is_symbol() {
        return "a symbol".into();
    }
    if value.is_function() {
        return "a function".into();
    }
    if is_array(value).unwrap_or(false) {
        return "an array".into();
    }
    match constructor_name(value) {
        Some(name) if name != "Object" => {
            let article = if name.starts_with(['A', 'E', 'I', 'O', 'U']) {
                "an"
            } else {
                "a"
            };
            format!("{article} {name}")
        }
        _ => "an object".into(),
    }
}

/// `value.constructor.name` when it can be read without an exception, else `None`.
fn constructor_name(value: &JsValue) -> Option<String> {
    let constructor = Reflect::get(value, &"constructor".into()).ok()?;
    if !constructor.is_function() {
        return None;
    }
    let name = Reflect::get(&constructor, &"name".into()).ok()?;
    let name = name.dyn_ref::<JsString>()?;
    (name.length() > 0 && name.length() <= QUOTE_CHARS).then(|| String::from(name))
}

/// A foreign string in quotes, cut to [`QUOTE_CHARS`] (the whole string never enters wasm).
fn quote(s: &JsString) -> String {
    if s.length() <= QUOTE_CHARS {
        format!("{:?}", String::from(s))
    } else {
        format!("{:?}…", String::from(s.slice(0, QUOTE_CHARS)))
    }
}

/// What a caught exception says: its `message` if it has one, else how it looks.
pub(crate) fn exception_message(exception: &JsValue) -> String {
    let message = if exception.is_object() {
        Reflect::get(exception, &"message".into()).unwrap_or(JsValue::UNDEFINED)
    } else {
        exception.clone()
    };
    match message.dyn_ref::<JsString>() {
        Some(s) if s.length() <= 4 * QUOTE_CHARS => String::from(s),
        Some(s) => format!("{}…", String::from(s.slice(0, 4 * QUOTE_CHARS))),
        None => describe(exception),
    }
}

/// Reads one parameter object whose keys are declared up front: any other own string key is
/// refused by name at once (before any value is read, so a typo is reported as such), then
/// each declared key is read and type-checked on request. Absent and `undefined` keys are
/// "not given"; `null` is a wrong type. Symbol keys are ignored.
///
/// ```ignore
/// let mut r = ParamReader::object(&value, "spray parameter", &["spacing", "speed", "tool"])?;
/// let spacing = r.number("spacing")?;            // required: "… 'spacing' is missing"
/// let speed = r.optional_number("speed")?;       // Option<f64>
/// if let Some(mut tool) = r.optional_object("tool", &["width"])? {
///     let width = tool.number("width")?;         // messages say "tool.width"
/// }
/// // {spacng: 1} was refused by `object`: "unknown spray parameter 'spacng'"
/// ```
pub struct ParamReader {
    object: JsValue,
    /// Singular noun for messages, e.g. "segmentation parameter".
    noun: &'static str,
    /// Dotted path of this object inside the top-level one ("" or "spray.").
    prefix: String,
    depth: usize,
}

impl ParamReader {
    /// Starts reading `value`, which must be an object (not null, an array or a function)
    /// whose own string keys are all in `keys`. `noun` is singular: "segmentation parameter"
    /// gives "segmentation parameters must be an object, got null" and "unknown segmentation
    /// parameter 'x'".
    pub fn object(
        value: &JsValue,
        noun: &'static str,
        keys: &[&'static str],
    ) -> Result<ParamReader, ArgError> {
        let reader = ParamReader {
            object: value.clone(),
            noun,
            prefix: String::new(),
            depth: 0,
        };
        reader.check(&format!("{noun}s"), keys)?;
        Ok(reader)
    }

    /// Like [`ParamReader::object`] for an optional argument: `undefined` gives `None`.
    pub fn optional_argument(
        value: &JsValue,
        noun: &'static str,
        keys: &[&'static str],
    ) -> Result<Option<ParamReader>, ArgError> {
        if value.is_undefined() {
            return Ok(None);
        }
        ParamReader::object(value, noun, keys).map(Some)
    }

    /// Checks that `self.object` is an object and refuses own string keys not in `keys`,
    /// without reading their values. `what` names the object in messages.
    fn check(&self, what: &str, keys: &[&'static str]) -> Result<(), ArgError> {
        let value = &self.object;
        if !value.is_object() || is_array(value).unwrap_or(false) {
            return Err(ArgError(format!(
                "{what} must be an object, got {}",
                describe(value)
            )));
        }
        let own = Reflect::own_keys(value).map_err(|e| {
            ArgError(format!(
                "listing the keys of {what} threw: {}",
                exception_message(&e)
            ))
        })?;
        for i in 0..own.length() {
            let key = own.get(i);
            let Some(key) = key.dyn_ref::<JsString>() else {
                continue;
            };
            let known = key.length() <= MAX_STRING && {
                let key = String::from(key);
                keys.iter().any(|k| *k == key)
            };
            if !known {
                let shown = if key.length() <= QUOTE_CHARS {
                    String::from(key)
                } else {
                    format!("{}…", String::from(key.slice(0, QUOTE_CHARS)))
                };
                return Err(ArgError(format!(
                    "unknown {} '{}'",
                    self.noun,
                    self.name(&shown)
                )));
            }
        }
        Ok(())
    }

    /// The dotted name of `key` as messages show it.
    fn name(&self, key: &str) -> String {
        format!("{}{key}", self.prefix)
    }

    /// `Reflect.get(object, key)`; `None` when absent or `undefined`.
    fn get(&self, key: &'static str) -> Result<Option<JsValue>, ArgError> {
        match Reflect::get(&self.object, &JsValue::from_str(key)) {
            Ok(v) if v.is_undefined() => Ok(None),
            Ok(v) => Ok(Some(v)),
            Err(e) => Err(ArgError(format!(
                "reading {} '{}' threw: {}",
                self.noun,
                self.name(key),
                exception_message(&e)
            ))),
        }
    }

    fn missing(&self, key: &str) -> ArgError {
        ArgError(format!("{} '{}' is missing", self.noun, self.name(key)))
    }

    fn wrong_type(&self, key: &str, wanted: &str, value: &JsValue) -> ArgError {
        ArgError(format!(
            "{} must be {wanted}, got {}",
            self.name(key),
            describe(value)
        ))
    }

    /// A number (NaN and ±Infinity pass: the core refuses them with the range it allows).
    pub fn optional_number(&self, key: &'static str) -> Result<Option<f64>, ArgError> {
        match self.get(key)? {
            None => Ok(None),
            Some(v) => match v.as_f64() {
                Some(x) => Ok(Some(x)),
                None => Err(self.wrong_type(key, "a number", &v)),
            },
        }
    }

    /// A required number.
    pub fn number(&self, key: &'static str) -> Result<f64, ArgError> {
        self.optional_number(key)?.ok_or_else(|| self.missing(key))
    }

    /// A whole number in `min..=max` (counts, ids), refused with the range otherwise.
    pub fn optional_integer(
        &self,
        key: &'static str,
        min: i64,
        max: i64,
    ) -> Result<Option<i64>, ArgError> {
        match self.get(key)? {
            None => Ok(None),
            Some(v) => integer(&v, &self.name(key), min, max).map(Some),
        }
    }

    /// `true` or `false`.
    pub fn optional_bool(&self, key: &'static str) -> Result<Option<bool>, ArgError> {
        match self.get(key)? {
            None => Ok(None),
            Some(v) => match v.as_bool() {
                Some(b) => Ok(Some(b)),
                None => Err(self.wrong_type(key, "true or false", &v)),
            },
        }
    }

    /// One of `choices` (exact spelling); returns the matching entry of `choices`.
    pub fn optional_choice(
        &self,
        key: &'static str,
        choices: &[&'static str],
    ) -> Result<Option<&'static str>, ArgError> {
        let Some(v) = self.get(key)? else {
            return Ok(None);
        };
        let found = v
            .dyn_ref::<JsString>()
            .filter(|s| s.length() <= MAX_STRING)
            .map(String::from)
            .and_then(|s| choices.iter().copied().find(|c| *c == s));
        found.map(Some).ok_or_else(|| {
            let listed: Vec<String> = choices.iter().map(|c| format!("{c:?}")).collect();
            self.wrong_type(key, &format!("one of {}", listed.join(", ")), &v)
        })
    }

    /// A string of at most 256 characters.
    pub fn optional_string(&self, key: &'static str) -> Result<Option<String>, ArgError> {
        let Some(v) = self.get(key)? else {
            return Ok(None);
        };
        match v.dyn_ref::<JsString>() {
            Some(s) if s.length() <= MAX_STRING => Ok(Some(String::from(s))),
            Some(_) => Err(ArgError(format!(
                "{} must be at most {MAX_STRING} characters long",
                self.name(key)
            ))),
            None => Err(self.wrong_type(key, "a string", &v)),
        }
    }

    /// Three numbers `[x, y, z]` (an array or a typed array of length 3).
    pub fn optional_vector3(&self, key: &'static str) -> Result<Option<[f64; 3]>, ArgError> {
        self.get(key)?
            .map(|v| read_vector3(&v, &self.name(key)))
            .transpose()
    }

    /// The raw value of `key` (`None` when absent or `undefined`), for a caller that
    /// dispatches on its type itself (a list of points or ids, "mesh" or a number).
    pub(crate) fn optional_value(&self, key: &'static str) -> Result<Option<JsValue>, ArgError> {
        self.get(key)
    }

    /// A list of exactly `count` parameter objects with the declared `keys` (messages say
    /// "key[i].inner"); `None` when absent. Elements are read through catching imports.
    pub fn optional_objects(
        &self,
        key: &'static str,
        count: u32,
        keys: &[&'static str],
    ) -> Result<Option<Vec<ParamReader>>, ArgError> {
        let Some(v) = self.get(key)? else {
            return Ok(None);
        };
        let name = self.name(key);
        self.check_depth(&name)?;
        if !is_array(&v).unwrap_or(false) {
            return Err(self.wrong_type(key, &format!("an array of {count} objects"), &v));
        }
        let length = v.unchecked_ref::<js_sys::Array>().length();
        if length != count {
            return Err(ArgError(format!(
                "{name} must list exactly {count} entries, got {length}"
            )));
        }
        let mut out = Vec::with_capacity(count as usize);
        for i in 0..count {
            let item = Reflect::get_u32(&v, i).map_err(|e| {
                ArgError(format!(
                    "reading {name}[{i}] threw: {}",
                    exception_message(&e)
                ))
            })?;
            out.push(self.nested(item, &format!("{name}[{i}]"), keys)?);
        }
        Ok(Some(out))
    }

    /// A nested parameter object with its own declared `keys`, read with its own reader
    /// (messages say "key.inner"). Refused beyond [`MAX_DEPTH`], so a schema cannot recurse
    /// without bound.
    pub fn optional_object(
        &self,
        key: &'static str,
        keys: &[&'static str],
    ) -> Result<Option<ParamReader>, ArgError> {
        let Some(v) = self.get(key)? else {
            return Ok(None);
        };
        let name = self.name(key);
        self.check_depth(&name)?;
        self.nested(v, &name, keys).map(Some)
    }

    /// Refuses to open an object below this one at [`MAX_DEPTH`].
    fn check_depth(&self, name: &str) -> Result<(), ArgError> {
        if self.depth >= MAX_DEPTH {
            return Err(ArgError(format!(
                "{name} is nested more than {MAX_DEPTH} objects deep"
            )));
        }
        Ok(())
    }

    /// A reader one level down for `object`, named `name` in messages, with its declared keys.
    fn nested(
        &self,
        object: JsValue,
        name: &str,
        keys: &[&'static str],
    ) -> Result<ParamReader, ArgError> {
        let reader = ParamReader {
            object,
            noun: self.noun,
            prefix: format!("{name}."),
            depth: self.depth + 1,
        };
        reader.check(name, keys)?;
        Ok(reader)
    }
}

/// A whole number in `min..=max`, or an error naming `name`, the value and the range.
/// `min..=max` must lie within ±2^53 so every whole number in it is exact.
pub(crate) fn integer(value: &JsValue, name: &str, min: i64, max: i64) -> Result<i64, ArgError> {
    let range = || format!("from {min} to {max}");
    let Some(x) = value.as_f64() else {
        return Err(ArgError(format!(
            "{name} must be a whole number {}, got {}",
            range(),
            describe(value)
        )));
    };
    // Exact for |x| < 2^53, and min/max lie within that, so the cast below is exact too.
    if x.fract() != 0.0 || !(min as f64..=max as f64).contains(&x) {
        return Err(ArgError(format!(
            "{name} must be a whole number {}, got {}",
            range(),
            Compact(x)
        )));
    }
    Ok(x as i64)
}

/// Three numbers `[x, y, z]`: an array, a `Float64Array` or a `Float32Array` of length 3
/// (NaN and ±Infinity pass: callers refuse them with what they allow). `name` names the
/// value in messages.
pub(crate) fn read_vector3(value: &JsValue, name: &str) -> Result<[f64; 3], ArgError> {
    let wanted = || {
        ArgError(format!(
            "{name} must be three numbers [x, y, z], got {}",
            describe(value)
        ))
    };
    let is_list = is_array(value).unwrap_or(false)
        || value.is_instance_of::<js_sys::Float64Array>()
        || value.is_instance_of::<js_sys::Float32Array>();
    if !is_list {
        return Err(wanted());
    }
    let length = Reflect::get(value, &"length".into())
        .ok()
        .and_then(|l| l.as_f64());
    if length != Some(3.0) {
        return Err(wanted());
    }
    let mut out = [0.0; 3];
    for (i, slot) in out.iter_mut().enumerate() {
        let item = Reflect::get_u32(value, i as u32).map_err(|e| {
            ArgError(format!(
                "reading {name}[{i}] threw: {}",
                exception_message(&e)
            ))
        })?;
        *slot = item.as_f64().ok_or_else(|| {
            ArgError(format!(
                "{name}[{i}] must be a number, got {}",
                describe(&item)
            ))
        })?;
    }
    Ok(out)
}

/// Largest byte array the engine takes. A single wasm32 allocation cannot exceed
/// `isize::MAX` (2^31 − 1) bytes; copying more traps, so it is refused before any copy.
pub(crate) const MAX_BYTES: u32 = i32::MAX as u32;

/// A `Uint8Array` or `ArrayBuffer` as a byte view of checked length (`None` when empty or
/// detached), so that an oversize file gets a message rather than a trap in the allocator.
/// `what` names the input.
pub(crate) fn byte_array(value: &JsValue, what: &str) -> Result<Option<Uint8Array>, ArgError> {
    if !(value.is_instance_of::<Uint8Array>() || value.is_instance_of::<js_sys::ArrayBuffer>()) {
        return Err(ArgError(format!(
            "{what} must be a Uint8Array or an ArrayBuffer, got {}",
            describe(value)
        )));
    }
    // `byteLength` as a number: the bindings' lengths are u32 and would wrap above 4 GiB.
    let byte_length = Reflect::get(value, &"byteLength".into())
        .ok()
        .and_then(|v| v.as_f64())
        .unwrap_or(0.0);
    if byte_length > MAX_BYTES as f64 {
        return Err(ArgError(format!(
            "the file is {} bytes; the engine can hold at most {MAX_BYTES} bytes (2 GiB − 1)",
            Compact(byte_length)
        )));
    }
    if byte_length == 0.0 {
        // Also a detached buffer, which `new Uint8Array(buffer)` would throw on.
        return Ok(None);
    }
    let array = match value.dyn_ref::<js_sys::ArrayBuffer>() {
        Some(buffer) => Uint8Array::new(buffer),
        None => value.clone().unchecked_into(),
    };
    // `copy_to` sizes its copy by `length()`, so the views copied must match it exactly.
    let len = array.length();
    if f64::from(len) != byte_length {
        return Err(ArgError(format!(
            "{what} reports {len} elements but {} bytes; pass a plain Uint8Array",
            Compact(byte_length)
        )));
    }
    Ok(Some(array))
}

/// Bytes `start..start + into.len()` of `array` (within its length) copied into `into`.
pub(crate) fn copy_bytes(array: &Uint8Array, start: u32, into: &mut [u8]) {
    let end = start + into.len() as u32;
    array.subarray(start, end).copy_to(into);
}

/// An optional `(stage, fraction) => void` callback: a function, or `undefined`/`null`.
pub(crate) fn read_callback(
    value: Option<JsValue>,
    name: &str,
) -> Result<Option<js_sys::Function>, ArgError> {
    match value {
        None => Ok(None),
        Some(v) if v.is_function() => Ok(Some(v.unchecked_into())),
        Some(v) => Err(ArgError(format!(
            "{name} must be a function, got {}",
            describe(&v)
        ))),
    }
}

/// Largest element count of an index list (face ids): more than any mesh the engine holds.
const MAX_INDEX_LIST: u32 = 1 << 28;

/// An optional list of indices (face ids): a `Uint32Array`, or an array of whole numbers from
/// 0 to 2^32 − 1; `undefined` or `null` gives `None`. `name` names the argument in messages.
pub(crate) fn read_index_list(
    value: Option<JsValue>,
    name: &str,
) -> Result<Option<Vec<u32>>, ArgError> {
    let Some(value) = value.filter(|v| !v.is_undefined() && !v.is_null()) else {
        return Ok(None);
    };
    if let Some(typed) = value.dyn_ref::<js_sys::Uint32Array>() {
        return Ok(Some(typed.to_vec()));
    }
    if !is_array(&value).unwrap_or(false) {
        return Err(ArgError(format!(
            "{name} must be a Uint32Array or an array of face ids, got {}",
            describe(&value)
        )));
    }
    let array: &js_sys::Array = value.unchecked_ref();
    if array.length() > MAX_INDEX_LIST {
        return Err(ArgError(format!(
            "{name} has {} entries, more than the {MAX_INDEX_LIST} the engine takes",
            array.length()
        )));
    }
    let mut out = Vec::with_capacity(array.length() as usize);
    for i in 0..array.length() {
        let item = Reflect::get_u32(&value, i).map_err(|e| {
            ArgError(format!(
                "reading {name}[{i}] threw: {}",
                exception_message(&e)
            ))
        })?;
        out.push(integer(&item, &format!("{name}[{i}]"), 0, u32::MAX as i64)? as u32);
    }
    Ok(Some(out))
}

/// Largest element count of a number list (point coordinates): more than any source needs.
const MAX_NUMBER_LIST: u32 = 1 << 26;

/// A list of numbers (point coordinates): a `Float64Array`, a `Float32Array` or an array of
/// numbers, whose length is a multiple of `group` (3 for xyz). NaN and ±Infinity are refused
/// by name with their index. `name` names the argument in messages.
pub(crate) fn read_number_list(
    value: &JsValue,
    name: &str,
    group: u32,
) -> Result<Vec<f64>, ArgError> {
    let wanted = || {
        let per = match group {
            1 => String::new(),
            _ => format!(" ({group} per point)"),
        };
        format!(
            "{name} must be a Float64Array or an array of numbers{per}, got {}",
            describe(value)
        )
    };
    let out = if let Some(typed) = value.dyn_ref::<js_sys::Float64Array>() {
        check_list_length(typed.length(), name)?;
        typed.to_vec()
    } else if let Some(typed) = value.dyn_ref::<js_sys::Float32Array>() {
        check_list_length(typed.length(), name)?;
        typed.to_vec().into_iter().map(f64::from).collect()
    } else if is_array(value).unwrap_or(false) {
        let array: &js_sys::Array = value.unchecked_ref();
        check_list_length(array.length(), name)?;
        let mut out = Vec::with_capacity(array.length() as usize);
        for i in 0..array.length() {
            let item = Reflect::get_u32(value, i).map_err(|e| {
                ArgError(format!(
                    "reading {name}[{i}] threw: {}",
                    exception_message(&e)
                ))
            })?;
            out.push(item.as_f64().ok_or_else(|| {
                ArgError(format!(
                    "{name}[{i}] must be a number, got {}",
                    describe(&item)
                ))
            })?);
        }
        out
    } else {
        return Err(ArgError(wanted()));
    };
    if out.len() % group as usize != 0 {
        return Err(ArgError(format!(
            "{name} has {} numbers, not a multiple of {group} ({group} per point)",
            out.len()
        )));
    }
    if let Some(i) = out.iter().position(|x| !x.is_finite()) {
        return Err(ArgError(format!(
            "{name}[{i}] must be a finite number, got {}",
            Compact(out[i])
        )));
    }
    Ok(out)
}

fn check_list_length(length: u32, name: &str) -> Result<(), ArgError> {
    if length > MAX_NUMBER_LIST {
        return Err(ArgError(format!(
            "{name} has {length} entries, more than the {MAX_NUMBER_LIST} the engine takes"
        )));
    }
    Ok(())
}

/// Sets `object[key] = value` on a result object being built.
pub(super) fn set(object: &js_sys::Object, key: &str, value: &JsValue) -> Result<(), JsError> {
    Reflect::set(object, &JsValue::from_str(key), value)
        .map_err(|_| JsError::new(&format!("could not set {key} on the result")))?;
    Ok(())
}
